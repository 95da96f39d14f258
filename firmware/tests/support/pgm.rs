//! Shared by the benchmark and the fixture tests: the binary PGM inputs in `fixtures/bench/`.

/// Minimal binary PGM (P5, maxval <= 255) reader: `(width, height, pixels)`.
pub fn read_pgm(name: &str) -> (usize, usize, Vec<u8>) {
    let path = format!("{}/../fixtures/bench/{name}", env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    // Header: magic, width, height, maxval as whitespace-separated tokens ('#' comments),
    // then exactly one whitespace byte before the raster.
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 {
        while bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if bytes[i] == b'#' {
            while bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let start = i;
        while !bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        fields.push(String::from_utf8_lossy(&bytes[start..i]).into_owned());
    }
    assert_eq!(fields[0], "P5", "{path}: not a binary PGM");
    let (w, h): (usize, usize) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    assert!(fields[3].parse::<u32>().unwrap() <= 255, "{path}: 16-bit PGM");
    let data = bytes[i + 1..i + 1 + w * h].to_vec();
    (w, h, data)
}
