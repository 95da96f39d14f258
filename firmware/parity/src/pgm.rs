//! A binary PGM (P5, 8-bit) reader without `std`, for the benchmark inputs embedded in the
//! board image (the inputs of the thesis-size kernels, `fixtures/bench/`).

/// A parsed image borrowing its raster.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pgm<'a> {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Row-major pixels, exactly `width * height` of them.
    pub pixels: &'a [u8],
}

/// Why bytes are not an 8-bit binary PGM.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PgmError {
    /// The magic is not `P5`.
    NotP5,
    /// The header ends early or a field is not a decimal number.
    BadHeader,
    /// Maxval above 255 (16-bit samples) or 0.
    NotEightBit,
    /// Fewer raster bytes than width x height.
    Truncated,
}

/// Parses `bytes`: magic, width, height and maxval as whitespace-separated fields (with `#`
/// comments), one whitespace byte, then the raster.
pub fn parse(bytes: &[u8]) -> Result<Pgm<'_>, PgmError> {
    if bytes.get(..2) != Some(b"P5") {
        return Err(PgmError::NotP5);
    }
    let mut i = 2;
    let mut fields = [0usize; 3];
    for f in &mut fields {
        loop {
            match bytes.get(i) {
                Some(b) if b.is_ascii_whitespace() => i += 1,
                Some(b'#') => {
                    while bytes.get(i).is_some_and(|&b| b != b'\n') {
                        i += 1;
                    }
                }
                Some(_) => break,
                None => return Err(PgmError::BadHeader),
            }
        }
        let start = i;
        let mut v = 0usize;
        while let Some(&b) = bytes.get(i).filter(|b| b.is_ascii_digit()) {
            v = v.checked_mul(10).and_then(|v| v.checked_add(usize::from(b - b'0'))).ok_or(PgmError::BadHeader)?;
            i += 1;
        }
        if i == start {
            return Err(PgmError::BadHeader);
        }
        *f = v;
    }
    let [width, height, maxval] = fields;
    if maxval == 0 || maxval > 255 {
        return Err(PgmError::NotEightBit);
    }
    // Exactly one whitespace byte separates the header from the raster.
    if !bytes.get(i).is_some_and(u8::is_ascii_whitespace) {
        return Err(PgmError::BadHeader);
    }
    let n = width.checked_mul(height).ok_or(PgmError::BadHeader)?;
    let pixels = bytes.get(i + 1..).and_then(|r| r.get(..n)).ok_or(PgmError::Truncated)?;
    Ok(Pgm { width, height, pixels })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_fields_comments_and_errors() {
        let ok = b"P5\n# made by hand\n3 2\n255\n\x01\x02\x03\x04\x05\x06";
        assert_eq!(parse(ok), Ok(Pgm { width: 3, height: 2, pixels: &[1, 2, 3, 4, 5, 6] }));
        assert_eq!(parse(b"P2\n1 1\n255\n\x00"), Err(PgmError::NotP5));
        assert_eq!(parse(b"P5\n1 x\n255\n\x00"), Err(PgmError::BadHeader));
        assert_eq!(parse(b"P5\n1 1\n65535\n\x00\x00"), Err(PgmError::NotEightBit));
        assert_eq!(parse(b"P5\n2 2\n255\n\x00\x00\x00"), Err(PgmError::Truncated));
        assert_eq!(parse(b"P5\n2"), Err(PgmError::BadHeader));
        assert_eq!(parse(b"P5\n99999999999999999999999 1\n255\n"), Err(PgmError::BadHeader));
    }
}
