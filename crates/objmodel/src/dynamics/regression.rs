//! Local least-squares lines: the palm tilt's smoothing and its value at the onset.

/// Local linear regression smoothing of `y(t)` with half-width `h` \[s\].
pub(super) fn smooth(t: &[f64], y: &[f64], h: f64) -> Vec<f64> {
    (0..t.len())
        .map(|i| {
            let lo = t.partition_point(|&x| x < t[i] - h);
            let hi = t.partition_point(|&x| x <= t[i] + h);
            linear_at(&t[lo..hi], &y[lo..hi], t[i], 0.0).map_or(y[i], |r| r.0)
        })
        .collect()
}

/// Least-squares line through (t, y) evaluated at `at`, with its standard error for per-sample
/// noise `sigma`.
pub(super) fn linear_at(t: &[f64], y: &[f64], at: f64, sigma: f64) -> Option<(f64, f64, f64)> {
    let n = t.len() as f64;
    if n < 2.0 {
        return None;
    }
    let tm = t.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let stt: f64 = t.iter().map(|x| (x - tm).powi(2)).sum();
    let sty: f64 = t.iter().zip(y).map(|(a, b)| (a - tm) * (b - ym)).sum();
    let slope = if stt > 0.0 { sty / stt } else { 0.0 };
    let value = ym + slope * (at - tm);
    let se = sigma
        * (1.0 / n
            + if stt > 0.0 {
                (at - tm).powi(2) / stt
            } else {
                0.0
            })
        .sqrt();
    Some((value, se, slope))
}
