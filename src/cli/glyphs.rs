//! A 3x5 pixel font for the labels of the images the CLI writes (plot axes, contact-sheet
//! panels): digits, lower-case letters (drawn as capitals), `-`, `.` and space.

use image::{ImageBuffer, Pixel};

/// Rows of a glyph, top to bottom, 3 bits each (4 = left column).
fn glyph(ch: char) -> Option<[u8; 5]> {
    const DIGITS: [[u8; 5]; 10] = [
        [7, 5, 5, 5, 7],
        [2, 6, 2, 2, 7],
        [7, 1, 7, 4, 7],
        [7, 1, 7, 1, 7],
        [5, 5, 7, 1, 1],
        [7, 4, 7, 1, 7],
        [7, 4, 7, 5, 7],
        [7, 1, 1, 1, 1],
        [7, 5, 7, 5, 7],
        [7, 5, 7, 1, 7],
    ];
    const LETTERS: [[u8; 5]; 26] = [
        [2, 5, 7, 5, 5],
        [6, 5, 6, 5, 6],
        [3, 4, 4, 4, 3],
        [6, 5, 5, 5, 6],
        [7, 4, 6, 4, 7],
        [7, 4, 6, 4, 4],
        [3, 4, 5, 5, 3],
        [5, 5, 7, 5, 5],
        [7, 2, 2, 2, 7],
        [1, 1, 1, 5, 2],
        [5, 5, 6, 5, 5],
        [4, 4, 4, 4, 7],
        [5, 7, 7, 5, 5],
        [6, 5, 5, 5, 5],
        [2, 5, 5, 5, 2],
        [6, 5, 6, 4, 4],
        [2, 5, 5, 6, 3],
        [6, 5, 6, 5, 5],
        [3, 4, 2, 1, 6],
        [7, 2, 2, 2, 2],
        [5, 5, 5, 5, 7],
        [5, 5, 5, 5, 2],
        [5, 5, 7, 7, 5],
        [5, 5, 2, 5, 5],
        [5, 5, 2, 2, 2],
        [7, 1, 2, 4, 7],
    ];
    match ch {
        '0'..='9' => Some(DIGITS[ch as usize - '0' as usize]),
        'a'..='z' => Some(LETTERS[ch as usize - 'a' as usize]),
        'A'..='Z' => Some(LETTERS[ch as usize - 'A' as usize]),
        '-' => Some([0, 0, 7, 0, 0]),
        ' ' => Some([0; 5]),
        _ => None,
    }
}

/// Fills the `w` x `h` rectangle at (x, y), clipped to the image.
pub fn fill<P: Pixel>(
    img: &mut ImageBuffer<P, Vec<P::Subpixel>>,
    x: i64,
    y: i64,
    w: i64,
    h: i64,
    c: P,
) {
    for yy in y.max(0)..(y + h).min(i64::from(img.height())) {
        for xx in x.max(0)..(x + w).min(i64::from(img.width())) {
            img.put_pixel(xx as u32, yy as u32, c);
        }
    }
}

/// Writes `text` with its top-left corner at (x, y), each font pixel a `scale`-square of colour
/// `c`; glyphs advance 4 pixels, `.` 2, characters without a glyph 2 (blank).
pub fn draw_text<P: Pixel>(
    img: &mut ImageBuffer<P, Vec<P::Subpixel>>,
    x: i64,
    y: i64,
    text: &str,
    scale: i64,
    c: P,
) {
    let mut cx = x;
    for ch in text.chars() {
        match glyph(ch) {
            Some(rows) => {
                for (r, bits) in rows.iter().enumerate() {
                    for col in 0..3 {
                        if bits & (4 >> col) != 0 {
                            fill(img, cx + col * scale, y + r as i64 * scale, scale, scale, c);
                        }
                    }
                }
                cx += 4 * scale;
            }
            None => {
                if ch == '.' {
                    fill(img, cx, y + 4 * scale, scale, scale, c);
                }
                cx += 2 * scale;
            }
        }
    }
}
