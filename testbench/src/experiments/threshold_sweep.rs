//! The edge-threshold sweep behind Figs. 3.5-3.10: the corner detector in a 20x20 Foveal
//! window on the triangle path at 40 px/s, with the Watch and Peripheral windows to recover
//! (TPDF-CD) and alone, for TH = 10..100; one CSV row per threshold.
use super::setup::{corner0, run_scene, triangle};
use super::{Context, ExperimentError};
use crate::analysis::metrics::Summary;
use crate::frames::scene::{Scene, SceneConfig};
use crate::system::{Strategy, SystemConfig};
use coopwin_firmware::kernels::info::{corner_information, edge_information};
use std::fmt::Write as _;

/// One threshold's runs and measures.
pub struct ThresholdRow {
    /// The Sobel magnitude threshold TH.
    pub th: u16,
    /// With the Watch and Peripheral windows (multi-window).
    pub multi: Summary,
    /// The Foveal window alone.
    pub single: Summary,
    /// Edge pixels in frame 0's window at the corner.
    pub edges: u32,
    /// Their information, -log2 P, bits (Fig. 3.8).
    pub i_edge: f64,
    /// The proposed I_cd = 1/CLERR (Fig. 3.10).
    pub i_cd: f64,
}

impl ThresholdRow {
    /// TH as a chart's x.
    pub fn x(&self) -> f64 {
        f64::from(self.th)
    }
}

/// Runs the sweep (with clutter on the background when `clutter`) and writes its CSV.
pub fn sweep(ctx: &mut Context, clutter: bool) -> Result<Vec<ThresholdRow>, ExperimentError> {
    let mut csv = String::from("threshold,mean_x,mean_y,rms,rlt_multi,rlt_single,edge_pixels,i_edge,i_cd\n");
    let mut rows = Vec::new();
    for th in (1..=10).map(|k| k * 10) {
        ctx.say(&format!("TH {th}"));
        let scene = SceneConfig { clutter, noise: 2.0, ..triangle(40.0, 3) };
        let target = Some(corner0(&scene));
        let mut cfg = ctx.config(SystemConfig::thesis(Strategy::TpdfCd, ctx.profile, target));
        cfg.params.corner_threshold = th;
        cfg.params.foveal = 20;
        let (_, multi) = run_scene(&cfg, scene.clone())?;
        cfg.strategy = Strategy::SingleCd;
        let (_, single) = run_scene(&cfg, scene.clone())?;
        let (edges, total) = edge_count(&scene, th);
        let i_edge = edge_information(edges, total);
        let i_cd = corner_information(multi.rms).unwrap_or(0.0);
        let _ = writeln!(
            csv,
            "{th},{:.3},{:.3},{:.3},{:.3},{:.3},{edges},{i_edge:.1},{i_cd:.3}",
            multi.mean_x, multi.mean_y, multi.rms, multi.rlt, single.rlt
        );
        rows.push(ThresholdRow { th, multi, single, edges, i_edge, i_cd });
    }
    ctx.write_csv(&csv)?;
    Ok(rows)
}

/// Edge pixels (Sobel magnitude over TH) in the 20x20 window at the corner of frame 0, and
/// the pixels looked at.
fn edge_count(scene: &SceneConfig, th: u16) -> (u32, u32) {
    let s = Scene::new(scene.clone());
    let (img, t) = s.render(0);
    let (cx, cy) = (t.corner.0.round() as usize, t.corner.1.round() as usize);
    let (x0, y0) = (cx.saturating_sub(10), cy.saturating_sub(10));
    let view = coopwin_firmware::kernels::view::WindowView::packed(&img, scene.width, scene.height).ok().and_then(|v| v.sub(x0, y0, 20, 20));
    let Some(view) = view else { return (0, 400) };
    let mut n = 0;
    for y in 1..19 {
        for x in 1..19 {
            if let Some((gx, gy)) = coopwin_firmware::kernels::corner::sobel_at(&view, x, y) {
                if f64::from(gx).hypot(f64::from(gy)) > f64::from(th) {
                    n += 1;
                }
            }
        }
    }
    (n, 18 * 18)
}
