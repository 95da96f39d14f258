//! The fields of a frame's payload on the links of thesis 2.2 and 2.6: little-endian numbers, and
//! what goes wrong decoding them.

/// A received payload could not be decoded into a message or position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// Unknown tag or source byte.
    BadTag,
    /// Wrong payload length.
    BadLength,
    /// A position that is NaN or infinite.
    NotFinite,
    /// A template chunk out of sequence, or without its header.
    BrokenTemplate,
}

error_messages!(DecodeError {
    BadTag => "unknown message tag or source byte",
    BadLength => "wrong payload length",
    NotFinite => "a position that is not a finite number",
    BrokenTemplate => "a template chunk out of sequence or without its header",
});

/// The little-endian `u16` at byte `i` (missing bytes read as 0).
pub(super) fn le16(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b.get(i).copied().unwrap_or(0), b.get(i + 1).copied().unwrap_or(0)])
}

/// The little-endian `u32` at byte `i` (missing bytes read as 0).
pub(super) fn le32(b: &[u8], i: usize) -> u32 {
    let g = |k: usize| b.get(i + k).copied().unwrap_or(0);
    u32::from_le_bytes([g(0), g(1), g(2), g(3)])
}
