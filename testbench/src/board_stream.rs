//! Records the COOP Foveal pair's window stream (thesis 4.2) for the Cortex-M4 replay
//! (`firmware/board`): the testbench's scene is rendered frame by frame, the pair's
//! requested window is cut from it, and the pair runs on it to choose the next window.
//! The file is `fixtures/board/windows.bin`; `tests/board_windows.rs` checks it is current.
use crate::scene::{PathKind, Scene, SceneConfig};
use coopwin_firmware::processors::Template;
use coopwin_firmware::types::Point;
use coopwin_firmware::kernels::view::WindowView;
use coopwin_parity::stream::{encode, Frame};
use coopwin_parity::suite::{CoopPair, NoMeter};

/// The recorded run: the triangle path at 150 px/s under the lamp change, with noise, so both
/// the NCC and the corner detector are chosen (the lamp's middle third) within 48 frames.
pub fn scene() -> SceneConfig {
    SceneConfig { path: PathKind::Triangle, speed: 150.0, frames: 48, lighting_ramp: true, noise: 2.0, seed: 7, ..SceneConfig::default() }
}

/// The stream's bytes; it ends early if the pair loses the target.
pub fn record(cfg: &SceneConfig) -> Result<Vec<u8>, String> {
    let scene = Scene::new(cfg.clone());
    let (w, h) = (cfg.width, cfg.height);
    let (frame0, truth) = scene.render(0);
    let start = Point { x: truth.corner.0 as f32, y: truth.corner.1 as f32 };
    let view = WindowView::packed(&frame0, w, h).map_err(|e| format!("frame 0: {e}"))?;
    let tpl = Template::capture(&view, start, 20).ok_or("the template does not fit in frame 0")?;
    let mut pair = CoopPair::new(tpl.clone(), start);
    let mut windows: Vec<(f64, [u16; 4], Vec<u8>)> = Vec::new();
    for k in 0..cfg.frames {
        let Some(r) = pair.want() else { break };
        let (img, _) = if k == 0 { (frame0.clone(), truth) } else { scene.render(k) };
        let (x0, y0, ww, wh) = (usize::from(r.x0), usize::from(r.y0), usize::from(r.width), usize::from(r.height));
        if x0 + ww > w || y0 + wh > h {
            return Err(format!("frame {k}: window {r:?} leaves the frame"));
        }
        let px: Vec<u8> = (y0..y0 + wh).flat_map(|y| img[y * w + x0..y * w + x0 + ww].iter().copied()).collect();
        let t = k as f64 / cfg.fps;
        let v = WindowView::new(&px, ww, wh, ww, r.x0.into(), r.y0.into()).map_err(|e| format!("frame {k}: {e}"))?;
        pair.frame(&mut NoMeter, &v, t).ok_or_else(|| format!("frame {k}: the partner sent no result"))?;
        windows.push((t, [r.x0, r.y0, r.width, r.height], px));
    }
    let frames: Vec<Frame<'_>> =
        windows.iter().map(|(t, [x0, y0, w, h], px)| Frame { t: *t, x0: *x0, y0: *y0, w: *w, h: *h, pixels: px }).collect();
    let side = u8::try_from(tpl.side()).map_err(|_| "template side over 255")?;
    let mut bytes = Vec::new();
    let a = tpl.anchor();
    encode(side, (a.x, a.y), tpl.pixels(), (start.x, start.y), &frames, &mut |b| bytes.extend_from_slice(b));
    Ok(bytes)
}
