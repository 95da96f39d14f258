//! The committed Verilog in hdl/verilog is what the blocks export today.
//! Regenerate with: cargo run --release -- verilog --out hdl/verilog

#[test]
fn committed_verilog_is_current() {
    for (name, text) in coopwin_hdl::verilog::exported(coopwin_hdl::verilog::DEFAULT_UNITS).unwrap()
    {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verilog").join(name);
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "{} is stale: run `cargo run --release -- verilog --out hdl/verilog`",
            path.display()
        );
    }
}

#[test]
fn network_has_the_contract_ports_for_each_unit() {
    let v = coopwin_hdl::verilog::window_network(4, 8);
    for k in 0..4 {
        for p in [
            "coord_strobe",
            "coord_data",
            "coord_ready",
            "decimate",
            "pixel_strobe",
            "pixel_out",
            "coord_error",
        ] {
            assert!(v.contains(&format!("{p}_{k};")), "{p}_{k}");
        }
    }
    assert_eq!(v.matches("window_unit unit_").count(), 4);
}
