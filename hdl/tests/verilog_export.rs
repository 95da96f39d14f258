//! The committed Verilog in hdl/verilog is what the export writes today.
//! Regenerate with: cargo run --release -- verilog --axis --out hdl/verilog
use coopwin_hdl::verilog::{axis_files, exported, window_network, Geometry, DEFAULT_UNITS};

#[test]
fn committed_verilog_is_current() {
    let wrapper = axis_files(DEFAULT_UNITS, &Geometry::CA_D1);
    for (name, text) in exported(DEFAULT_UNITS, &Geometry::CA_D1).into_iter().chain(wrapper) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verilog").join(name);
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "{} is stale: run `cargo run --release -- verilog --axis --out hdl/verilog`",
            path.display()
        );
    }
}

#[test]
fn network_has_the_contract_ports_for_each_unit() {
    let v = window_network(4, &Geometry::CA_D1);
    for k in 0..4 {
        for p in ["coord_strobe", "coord_data", "coord_ready", "decimate", "pixel_strobe", "pixel_out", "coord_error"] {
            assert!(v.contains(&format!("{p}_{k};")), "{p}_{k}");
        }
    }
    // The camera bus, the clock and the reset are shared, each declared once.
    for p in ["clock;", "reset;", "fval;", "lval;", "pixel_valid;", "[PIXEL_BITS-1:0] pixel;"] {
        assert_eq!(v.matches(p).count(), 1, "{p}");
    }
    assert_eq!(v.matches(") unit_").count(), 4);
}
