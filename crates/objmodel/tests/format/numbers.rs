//! Numbers: the decimal parser against `std`'s, bit for bit.

use super::*;

/// A random decimal string: sign, integer and fraction digits of many lengths, sometimes an
/// exponent, sometimes something that is not a number.
fn random_decimal(rng: &mut Rng) -> String {
    let mut s = String::new();
    match rng.below(4) {
        0 => s.push('-'),
        1 if rng.below(4) == 0 => s.push('+'),
        _ => {}
    }
    let int_len = [0, 1, 1, 2, 3, 10, 16, 19, 20, 25][rng.below(10) as usize];
    s.push_str(&rng.digits(int_len));
    if rng.below(5) != 0 {
        s.push('.');
        let frac_len = [0, 1, 3, 6, 9, 9, 12, 15, 17, 22, 23, 30][rng.below(12) as usize];
        s.push_str(&rng.digits(frac_len));
    }
    if rng.below(6) == 0 {
        s.push(['e', 'E'][rng.below(2) as usize]);
        if rng.below(2) == 0 {
            s.push('-');
        }
        let e = rng.below(330);
        s.push_str(&e.to_string());
    }
    if rng.below(50) == 0 {
        s.insert(
            rng.below(s.len() as u64 + 1) as usize,
            ['x', '.', '-', 'e'][rng.below(4) as usize],
        );
    }
    s
}

#[test]
fn float_parsing_matches_std_exactly() {
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut checked = 0;
    for _ in 0..20_000 {
        let s = random_decimal(&mut rng);
        let ours = format::parse_f64(s.as_bytes());
        let std = s.parse::<f64>().ok();
        assert_eq!(ours.map(f64::to_bits), std.map(f64::to_bits), "{s:?}");
        checked += usize::from(std.is_some());
    }
    assert!(checked > 15_000);
    for s in [
        "inf",
        "-inf",
        "+infinity",
        "NaN",
        "1e308",
        "1e309",
        "2.2250738585072014e-308",
        "9007199254740993",
        "9007199254740992.5",
        "0.1",
        "1700000000.008333",
        "4.9406564584124654e-324",
        "00000000000000000000001.5",
    ] {
        let (a, b) = (format::parse_f64(s.as_bytes()), s.parse::<f64>().ok());
        assert!(
            a.map(f64::to_bits) == b.map(f64::to_bits)
                || a.unwrap().is_nan() && b.unwrap().is_nan(),
            "{s}"
        );
    }

    // and through the reader, as TUM and CSV fields
    let mut tum = String::new();
    let mut csv = String::from("t,x,y,z,qx,qy,qz,qw\n");
    let mut expected = Vec::new();
    let mut i = 0;
    while expected.len() < 3000 {
        let f: Vec<String> = (0..3).map(|_| random_decimal(&mut rng)).collect();
        let v: Vec<f64> = f.iter().filter_map(|s| s.parse::<f64>().ok()).collect();
        if v.len() < 3 || v.iter().any(|x| !x.is_finite()) {
            continue;
        }
        i += 1;
        tum.push_str(&format!("{i} {} {} {} 0 0 0 1\n", f[0], f[1], f[2]));
        csv.push_str(&format!("{i}, {} ,{},{},0,0,0,1\n", f[0], f[1], f[2]));
        expected.push([v[0], v[1], v[2]]);
    }
    for (name, text) in [("f.tum", &tum), ("f.csv", &csv)] {
        let poses = read_str(name, text);
        assert_eq!(poses.len(), expected.len());
        for (p, e) in poses.iter().zip(&expected) {
            assert_eq!(xyz(p).map(f64::to_bits), e.map(f64::to_bits));
        }
    }
}
