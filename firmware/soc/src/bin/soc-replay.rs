//! The host's reference for the SoC co-simulation (scripts/soc.sh): runs the same
//! [`Tracker`] on the host, on windows cut from the frame files by a model of the window unit
//! (the rows and columns of the request, full resolution), on the frames the SoC's unit
//! delivered each window from (the simulation log's `window ... frame=K` lines), and compares
//! the position updates it would send with the bytes the SoC's UART sent, byte for byte.
//! With `--track CSV` (`coopwin track --strategy tpdf --target X,Y --fixed-template`'s rows,
//! the testbench's whole system on the behavioural units), it also requires an update for
//! every frame of the CSV with `ok` 1 and none for the others, each equal to the row's x, y
//! as the CSV prints them (3 decimals): the robot is sent what the tracker vouches for.
//!
//!   soc-replay --frames DIR --log sim.log --uart uart.bin --target X,Y [--track CSV]
use coopwin_firmware::kernels::view::WindowView;
use coopwin_firmware::ports::frame::FrameDecoder;
use coopwin_firmware::ports::position::{FramedPositionSink, PositionSink, PositionUpdate};
use coopwin_firmware::types::Point;
use coopwin_soc::{us_frame, Tracker};
use std::process::ExitCode;

const SIDE: usize = 256;

fn field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.split_whitespace().find_map(|w| w.strip_prefix(key).and_then(|r| r.strip_prefix('=')))
}

fn run() -> Result<String, String> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |k: &str| args.iter().position(|a| a == k).and_then(|i| args.get(i + 1)).cloned().ok_or(format!("missing {k} (usage: see the file's header)"));
    let (dir, log, uart, target) = (arg("--frames")?, arg("--log")?, arg("--uart")?, arg("--target")?);
    let (tx, ty) = target.split_once(',').ok_or("--target X,Y")?;
    let p = |s: &str| s.parse::<u32>().map_err(|e| format!("--target: {e}"));
    let mut tracker = Tracker::new(Point { x: p(tx)? as f32, y: p(ty)? as f32 });
    let log = std::fs::read_to_string(&log).map_err(|e| format!("{log}: {e}"))?;
    let got = std::fs::read(&uart).map_err(|e| format!("{uart}: {e}"))?;
    let mut want: Vec<u8> = Vec::new();
    let mut req = tracker.lock_on_window();
    let mut windows = 0;
    for line in log.lines().filter_map(|l| l.split_once(" window ").map(|(_, r)| r)) {
        let num = |k: &str| field(line, k).and_then(|v| v.parse::<usize>().ok()).ok_or(format!("log line without {k}: {line}"));
        let (frame, x0, y0) = (num("frame")?, num("x0")?, num("y0")?);
        if (x0, y0) != (usize::from(req.x0), usize::from(req.y0)) {
            return Err(format!("window {windows}: the SoC asked for ({x0}, {y0}), the host for ({}, {})", req.x0, req.y0));
        }
        let name = format!("{dir}/frame{frame:04}.raw");
        let img = std::fs::read(&name).map_err(|e| format!("{name}: {e}"))?;
        if img.len() != SIDE * SIDE {
            return Err(format!("{name}: {} bytes, not {SIDE}x{SIDE}", img.len()));
        }
        // The window unit's model: the request's rows and columns, in raster order.
        let (w, h) = req.delivered_size();
        let mut px = Vec::with_capacity(w * h);
        for y in usize::from(req.y0)..usize::from(req.y0) + h {
            px.extend_from_slice(&img[y * SIDE + usize::from(req.x0)..][..w]);
        }
        let view = WindowView::new(&px, w, h, w, u32::from(req.x0), u32::from(req.y0)).map_err(|e| format!("{e:?}"))?;
        let (update, next) = tracker.on_window(&view, frame as u32).map_err(|e| format!("{e:?}"))?;
        if let Some(u) = update {
            let mut sink = FramedPositionSink::new(&mut want);
            sink.emit(&u).map_err(|e| format!("{e:?}"))?;
        }
        windows += 1;
        match next {
            Some(r) => req = r,
            None => break,
        }
    }
    if windows == 0 {
        return Err("the log has no window lines".into());
    }
    if got != want {
        let at = got.iter().zip(&want).position(|(a, b)| a != b).unwrap_or(got.len().min(want.len()));
        return Err(format!("UART differs from the host at byte {at} (SoC {} bytes, host {} bytes)", got.len(), want.len()));
    }
    let mut said = format!("soc-replay: {windows} windows, {} UART bytes equal to the host's", got.len());
    if let Some(csv) = args.iter().position(|a| a == "--track").and_then(|i| args.get(i + 1)) {
        said += &format!("\nsoc-replay: {}", against_track(&got, csv)?);
    }
    Ok(said)
}

/// The UART's updates against `coopwin track`'s rows: one a row with `ok` 1, x and y as
/// printed.
fn against_track(uart: &[u8], csv: &str) -> Result<String, String> {
    let text = std::fs::read_to_string(csv).map_err(|e| format!("{csv}: {e}"))?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().ok_or(format!("{csv} is empty"))?.split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).ok_or(format!("{csv} has no {name} column"));
    let (fc, xc, yc, okc) = (col("frame")?, col("x")?, col("y")?, col("ok")?);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect::<Vec<_>>()).filter(|r| r.get(okc) == Some(&"1")).collect();
    let mut dec = FrameDecoder::new();
    let updates: Vec<PositionUpdate> = uart
        .iter()
        .filter_map(|&b| dec.feed(b))
        .map(|f| f.map_err(|e| format!("UART frame: {e:?}")).and_then(|p| PositionUpdate::decode(&p).map_err(|e| format!("UART update: {e:?}"))))
        .collect::<Result<_, _>>()?;
    if updates.len() != rows.len() {
        return Err(format!("{} UART updates for the CSV's {} rows with ok 1", updates.len(), rows.len()));
    }
    for (u, row) in updates.iter().zip(&rows) {
        let cell = |c: usize| row.get(c).copied().unwrap_or("");
        let frame = us_frame(u.t_us).to_string();
        let (x, y) = (format!("{:.3}", u.x), format!("{:.3}", u.y));
        if (frame.as_str(), x.as_str(), y.as_str()) != (cell(fc), cell(xc), cell(yc)) {
            return Err(format!("frame {frame}: the SoC sent ({x}, {y}), track's row {} says ({}, {})", cell(fc), cell(xc), cell(yc)));
        }
    }
    Ok(format!("{} updates equal to {csv}'s rows with ok 1 (frame, x, y)", updates.len()))
}

fn main() -> ExitCode {
    match run() {
        Ok(s) => {
            println!("{s}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("soc-replay: {e}");
            ExitCode::FAILURE
        }
    }
}
