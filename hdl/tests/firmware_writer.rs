//! The firmware's coordinate writer against the rust-hdl window unit at 640x480 (thesis 2.2.1,
//! B1.1, widened to two-byte coordinates): the writer refuses exactly the windows the unit's
//! `CoordPort` refuses (`coord_error`), and a set it writes is taken whole, eight bytes. The
//! reference is the simulated hardware; the set-size rule both use is the firmware's
//! `set_bytes`, so this checks the two sides of the port agree on everything else.
use coopwin_firmware::ports::window::{set_bytes, CoordinateWriter, WriteError};
use coopwin_firmware::types::{Decimation, WindowRequest};
use coopwin_hdl::sim::camera::{CameraBus, Window};
use coopwin_hdl::sim::driver::{queue_window, write_step, UnitDriver, UnitOutputs};
use proptest::prelude::*;

const SENSOR: (u16, u16) = (640, 480);

/// Clocks the unit with an idle camera until the writer is done and CRDY1 has fallen; the
/// outputs of the last clock.
fn handshake(unit: &mut UnitDriver<10, 10>, writer: &mut CoordinateWriter) -> UnitOutputs {
    let idle = CameraBus { fval: false, lval: false, pixel: 0, pixel_valid: false };
    let mut last = UnitOutputs::default();
    for _ in 0..200 {
        let port = write_step(writer, &last);
        last = unit.step(idle, port);
        if !writer.busy() && !last.coord_ready {
            // The set is judged on the clock after its last byte.
            let port = write_step(writer, &last);
            return unit.step(idle, port);
        }
    }
    panic!("the handshake did not finish in 200 clocks");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn the_writer_refuses_what_the_unit_refuses_at_640x480(
        x0 in 1u16..700, y0 in 1u16..540, width in 0u16..80, height in 0u16..80, decimate: bool,
    ) {
        let req = WindowRequest {
            x0, y0, width, height,
            decimation: if decimate { Decimation::Quarter } else { Decimation::Full },
        };
        let mut unit = UnitDriver::<10, 10>::new(usize::from(SENSOR.0), usize::from(SENSOR.1));
        let mut writer = CoordinateWriter::for_sensor(SENSOR.0, SENSOR.1);
        prop_assert_eq!(writer.set_len(), set_bytes(640, 480));
        let written = writer.write(&req);
        if written.is_err() {
            prop_assert_eq!(written, Err(WriteError::OutOfRange));
            // The same bounds as raw bytes (a zero width gives xmax = xmin - 1): the unit
            // refuses them too.
            let w = Window {
                xmin: u32::from(x0), xmax: u32::from(x0) + u32::from(width) - 1,
                ymin: u32::from(y0), ymax: u32::from(y0) + u32::from(height) - 1,
            };
            queue_window(&mut writer, w, decimate, true).unwrap();
        }
        let out = handshake(&mut unit, &mut writer);
        prop_assert_eq!(writer.sets_taken(), 1, "one whole eight-byte set");
        prop_assert_eq!(out.coord_error, written.is_err(), "{:?}", req);
    }
}
