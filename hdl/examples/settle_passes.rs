//! Settling passes per pixel clock of the direct-stepping driver over one CA-D1 frame, with a
//! window armed: the figure that sets the driver's speed (`docs/window-logic.md`, "Simulation
//! speed"). Run: cargo run --release -p coopwin-hdl --example settle_passes
use coopwin_hdl::sim::camera::{RasterTiming, Window};
use coopwin_firmware::ports::window::CoordinateWriter;
use coopwin_hdl::sim::driver::{queue_window, write_step, UnitDriver, UnitOutputs};

fn main() {
    let t = RasterTiming::CA_D1;
    let mut unit = UnitDriver::<8, 8>::default();
    let mut writer = CoordinateWriter::new();
    queue_window(&mut writer, Window { xmin: 100, xmax: 139, ymin: 100, ymax: 139 }, false, false).expect("an 8-bit window");
    let mut last = UnitOutputs::default();
    // The blanking lines, so the set arms the frame, then the frame.
    let lead = t.v_blank_lines * t.line_clocks();
    for c in 0..lead + t.frame_clocks() {
        let cam = t.bus_at((c + t.frame_clocks() - lead) % t.frame_clocks(), |x, y| (x ^ y) as u8);
        last = unit.step(cam, write_step(&mut writer, &last));
    }
    let clocks = lead + t.frame_clocks();
    println!("{:.2} settling passes per pixel clock", unit.passes() as f64 / clocks as f64);
}
