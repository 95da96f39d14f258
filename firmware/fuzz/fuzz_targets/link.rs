//! Link decoding on arbitrary bytes: never panics, and every message it yields encodes back
//! to payloads that decode to the same message.
#![no_main]
use coopwin_firmware::ports::frame::FrameDecoder;
use coopwin_firmware::ports::link::{message_payloads, MessageDecoder};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (mut frames, mut messages) = (FrameDecoder::new(), MessageDecoder::new());
    for &b in data {
        let Some(Ok(payload)) = frames.feed(b) else { continue };
        if let Some(Ok(m)) = messages.feed(&payload) {
            let mut again = MessageDecoder::new();
            let back: Vec<_> = message_payloads(&m).filter_map(|p| again.feed(&p)).collect();
            assert_eq!(back, [Ok(m)]);
        }
    }
});
