//! Tests of the AVX2 line scanner: it takes what the general scanner reads, bit for bit.

use super::super::tum::scan_tum;
use super::*;

/// `scan` on `text` line by line (each padded as in a buffer), against `scan_tum`: every
/// line taken must be one `scan_tum` reads as eight numbers with the same bits, and every
/// [`plain`] line must be taken while the table is in use. Returns the number of lines
/// taken, and of those with a field of more than 16 bytes.
fn check(shapes: &mut Shapes, text: &str) -> (usize, usize) {
    let (mut taken, mut long) = (0, 0);
    for line in text.split_inclusive('\n') {
        let mut b = line.as_bytes().to_vec();
        b.resize(b.len() + SIMD_WINDOW, b'7');
        // SAFETY: checked by the caller.
        let Some((v, end)) = (unsafe { shapes.scan(&b) }) else {
            assert!(shapes.given_up() || !plain(line), "{line:?} not taken");
            continue;
        };
        let sc = scan_tum(&b);
        assert_eq!(sc.end, end, "{line:?}");
        assert!(sc.count == 8 && sc.bad.is_none(), "{line:?}");
        assert_eq!(v.map(f64::to_bits), sc.vals.map(f64::to_bits), "{line:?}");
        taken += 1;
        long += usize::from(line.split_ascii_whitespace().any(|f| f.len() > 16));
    }
    (taken, long)
}

/// Deterministic test randomness ([`crate::testing::next`]).
struct Rng(rand::rngs::StdRng);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        crate::testing::next(&mut self.0) % n
    }
    fn digits(&mut self, n: usize) -> String {
        (0..n)
            .map(|_| char::from(b'0' + self.below(10) as u8))
            .collect()
    }
    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.below(xs.len() as u64) as usize]
    }
}

/// A column format of a writer: integer digits (0 for none), fraction digits (`None`: no
/// point), and which signs it prints.
type Column = (usize, Option<usize>, &'static str);

/// Mostly what writers print; now and then a column this scanner leaves to the scalar
/// one (more than 19 digits, a part of more than 16 in a long field).
fn column(rng: &mut Rng) -> Column {
    let (int, frac) = match rng.below(16) {
        0 => (0, Some(1 + rng.below(9) as usize)),
        1 => (1 + rng.below(3) as usize, None),
        2 => (1, Some(0)),
        3 => (10, Some(6)),
        4 => (17, Some(1)),
        5 => (1, Some(16 + rng.below(3) as usize)),
        6 => (16, Some(2 + rng.below(3) as usize)),
        7 => (1 + rng.below(3) as usize, Some(12 + rng.below(4) as usize)),
        _ => (1 + rng.below(3) as usize, Some(1 + rng.below(9) as usize)),
    };
    (
        int,
        frac,
        ["", "-", "+", "-+", "-", "-"][rng.below(6) as usize],
    )
}

fn number(rng: &mut Rng, (int, frac, signs): Column) -> String {
    let mut s = String::new();
    if !signs.is_empty() && rng.below(2) == 0 {
        s.push(signs.as_bytes()[rng.below(signs.len() as u64) as usize] as char);
    }
    s += &rng.digits(int);
    if let Some(f) = frac {
        s.push('.');
        s += &rng.digits(f);
    }
    s
}

/// A file's lines: a writer's columns and separators, and now and then a line spoiled
/// (a byte replaced, a field added or dropped, a comment, a huge value).
fn file(rng: &mut Rng, lines: usize) -> String {
    let columns: Vec<Column> = (0..8).map(|_| column(rng)).collect();
    let sep = rng.pick(&[" ", " ", "\t", "  ", " \r"]);
    let mut text = String::new();
    for _ in 0..lines {
        let mut fields: Vec<String> = columns.iter().map(|&c| number(rng, c)).collect();
        let mut line = String::new();
        match rng.below(12) {
            0 => {
                fields.pop();
            }
            1 => fields.push("0.5".into()),
            2 => fields[rng.below(8) as usize] = "9007199254740993".into(),
            3 => fields[rng.below(8) as usize] = "9007199254740992".into(),
            4 => line.push(' '),
            _ => {}
        }
        line += &fields.join(sep);
        if rng.below(10) == 0 {
            // A byte of the line replaced.
            let at = rng.below(line.len() as u64) as usize;
            let b = rng.pick(&["e", "#", "x", ".", "-", "+", " ", "\t", "\r", "5"]);
            line.replace_range(at..at + 1, b);
        }
        if rng.below(20) == 0 {
            line += " # comment";
        }
        text += &line;
        text.push('\n');
    }
    text
}

/// Random writers' files, lines spoiled now and then: every line taken is read as
/// `scan_tum` reads it, bit for bit, and most lines are taken.
#[test]
fn takes_what_scan_tum_reads_and_nothing_else() {
    if !available() {
        return;
    }
    let mut rng = Rng(crate::testing::rng(0x2545_f491_4f6c_dd1d));
    let (mut taken, mut long) = (0, 0);
    for _ in 0..3000 {
        let mut shapes = Shapes::default();
        let (t, l) = check(&mut shapes, &file(&mut rng, 40));
        taken += t;
        long += l;
    }
    // Of 120000 lines, many are taken, some with fields of two runs.
    assert!(
        taken > 5000 && long > 500,
        "{taken} taken, {long} with long fields"
    );
}

/// A file whose lines all have new shapes stops being looked up after 256 lines.
#[test]
fn gives_up_on_ever_changing_shapes() {
    if !available() {
        return;
    }
    let mut shapes = Shapes::default();
    let mut text = String::new();
    for i in 0..400 {
        // Eight fields, the first with as many digits as `i` needs.
        text += &format!("{i} 1 2 3 4 5 6 1\n");
    }
    let (taken, _) = check(&mut shapes, &text);
    // Lines 0..=255 each bring a new shape (or one of 0..9, 10..99, 100..999 three
    // shapes: the test counts what is taken), then the table is dropped.
    assert!(taken > 200, "{taken}");
    let (again, _) = check(&mut shapes, &text);
    assert_eq!(again, 400, "shapes are few: the table is still used");
    let mut changing = Shapes::default();
    let mut text = String::new();
    for i in 0..400 {
        text += &format!("{} 1 2 3 4 5 6 1\n", "1".repeat(1 + i % 19));
        text += &format!("1 {} 2 3 4 5 6 1\n", "2".repeat(1 + i % 17));
    }
    let (taken, _) = check(&mut changing, &text);
    assert!(taken < 300, "{taken} of 800 lines taken, table kept");
}

/// A line that must be taken: shorter than 128 bytes, and eight fields of a sign or none,
/// at least one and at most 15 digits and at most one point, at most 16 bytes after the
/// sign, separated by spaces, tabs or `\r`.
fn plain(line: &str) -> bool {
    let fields: Vec<&str> = line
        .split([' ', '\t', '\r', '\n'])
        .filter(|f| !f.is_empty())
        .collect();
    line.len() < 128
        && line.ends_with('\n')
        && line.bytes().all(|b| b" \t\r\n.-+0123456789".contains(&b))
        && fields.len() == 8
        && fields.iter().all(|f| {
            let body = f.strip_prefix(['-', '+']).unwrap_or(f);
            let digits = body.bytes().filter(u8::is_ascii_digit).count();
            let points = body.bytes().filter(|&b| b == b'.').count();
            body.len() == digits + points
                && body.len() <= 16
                && (1..=15).contains(&digits)
                && points <= 1
        })
}

#[test]
fn takes_the_lines_of_a_pose_file() {
    if !available() {
        return;
    }
    let text = "1700000000.008333 0.500133158 -0.200139966 0.899898932 -0.000001866 \
                -0.000027228 0.258836509 0.965921146\n\
                1700000000.016667 0.500133159 -0.200139961 0.899898933 0.000001866 \
                -0.000027221 0.258836507 0.965921147\n";
    let mut shapes = Shapes::default();
    // Twice: the first time each shape is new, the second time it is known.
    assert_eq!(check(&mut shapes, text), (2, 2));
    assert_eq!(check(&mut shapes, text), (2, 2));
    assert_eq!(shapes.misses, 2);
}
