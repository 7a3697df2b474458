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

/// The least-squares line through (t, y): the number of points, the means of t and y, the
/// sum of squares of t about its mean, and the slope (0 when every t is the same).
fn line(t: &[f64], y: &[f64]) -> Option<(f64, f64, f64, f64, f64)> {
    let n = t.len() as f64;
    if n < 2.0 {
        return None;
    }
    let tm = t.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let stt: f64 = t.iter().map(|x| (x - tm).powi(2)).sum();
    let sty: f64 = t.iter().zip(y).map(|(a, b)| (a - tm) * (b - ym)).sum();
    let slope = if stt > 0.0 { sty / stt } else { 0.0 };
    Some((n, tm, ym, stt, slope))
}

/// Least-squares line through (t, y) evaluated at `at`, with its standard error for per-sample
/// noise `sigma`, and the line's slope.
pub(super) fn linear_at(t: &[f64], y: &[f64], at: f64, sigma: f64) -> Option<(f64, f64, f64)> {
    let (n, tm, ym, stt, slope) = line(t, y)?;
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

/// The slope of the least-squares line through (t, y) and its standard deviation for
/// per-sample noise `sigma` (infinite when every t is the same).
pub(super) fn slope(t: &[f64], y: &[f64], sigma: f64) -> Option<(f64, f64)> {
    let (_, _, _, stt, slope) = line(t, y)?;
    Some((slope, sigma / stt.sqrt()))
}
