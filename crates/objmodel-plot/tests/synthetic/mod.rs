//! Synthetic data shaped like a palm-toppling demonstration, shared by the tests and the
//! `samples` example.
#![allow(dead_code)]

use objmodel_plot::{AngleSeries, Fig8, Outline, SideView};

/// Palm tilt ramps up at 10°/s; the box stays put on the palm until the tilt reaches
/// φ = 20° (t = 2 s), then topples 90° relative to the palm in 0.6 s.
pub fn fig8() -> Fig8 {
    let phi = 20f64.to_radians();
    let rate = 10f64.to_radians();
    let onset = phi / rate;
    let t: Vec<f64> = (0..=350).map(|i| i as f64 * 0.01).collect();
    let palm: Vec<f64> = t
        .iter()
        .map(|&t| (rate * t).min(26f64.to_radians()))
        .collect();
    let rel: Vec<f64> = t
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let s = ((t - onset) / 0.6).clamp(0.0, 1.0);
            let wiggle = 0.004 * ((i * 7919) % 13) as f64 / 13.0; // measurement noise
            std::f64::consts::FRAC_PI_2 * (1.0 - (std::f64::consts::PI * s).cos()) / 2.0 + wiggle
        })
        .collect();
    let k = (onset / 0.01).round() as usize;
    Fig8 {
        title: "Box toppling on the palm".to_owned(),
        series: vec![
            AngleSeries {
                label: "box angle relative to palm".to_owned(),
                t: t.clone(),
                angle_rad: rel.clone(),
            },
            AngleSeries {
                label: "palm tilt".to_owned(),
                t: t.clone(),
                angle_rad: palm.clone(),
            },
        ],
        onset_t: Some(onset),
        phi_rad: Some(phi),
        marks: vec![
            ("ψe box".to_owned(), t[k], rel[k]),
            ("ψe palm".to_owned(), t[k], palm[k]),
        ],
    }
}

fn rotate(points: &[[f64; 2]], pivot: [f64; 2], angle: f64) -> Vec<[f64; 2]> {
    let (s, c) = angle.sin_cos();
    points
        .iter()
        .map(|p| {
            let (dx, dy) = (p[0] - pivot[0], p[1] - pivot[1]);
            [pivot[0] + c * dx - s * dy, pivot[1] + s * dx + c * dy]
        })
        .collect()
}

/// A 0.08 m × 0.16 m box on a 0.30 m × 0.02 m palm that tilts (clockwise, about the palm's
/// centre) at four instants: at rest, tilted with the box, box toppling about its lower right
/// edge, box resting on its side.
pub fn side_view() -> SideView {
    let palm = vec![[-0.15, -0.02], [0.15, -0.02], [0.15, 0.0], [-0.15, 0.0]];
    let boxp = vec![[0.0, 0.0], [0.08, 0.0], [0.08, 0.16], [0.0, 0.16]];
    let edge = [0.08, 0.0];
    let frames = [
        (0.0, 0.0, 0.0),
        (1.0, 10.0, 0.0),
        (2.3, 20.0, 40.0),
        (3.0, 20.0, 90.0),
    ];
    SideView {
        title: "Toppling seen along the edge".to_owned(),
        frames: frames
            .iter()
            .map(|&(t, tilt_deg, topple_deg)| {
                let tilt = -f64::to_radians(tilt_deg);
                let b = rotate(&boxp, edge, -f64::to_radians(topple_deg));
                (
                    t,
                    vec![
                        Outline {
                            label: "palm".to_owned(),
                            points: rotate(&palm, [0.0, 0.0], tilt),
                        },
                        Outline {
                            label: "box".to_owned(),
                            points: rotate(&b, [0.0, 0.0], tilt),
                        },
                    ],
                )
            })
            .collect(),
    }
}

/// Two curves, one with a gap (NaN) in the middle.
pub fn xy_series() -> Vec<(String, Vec<(f64, f64)>)> {
    let a = (0..=200)
        .map(|i| {
            let x = i as f64 * 0.05;
            (x, (x).sin() * (-0.1 * x).exp())
        })
        .collect();
    let b = (0..=200)
        .map(|i| {
            let x = i as f64 * 0.05;
            (
                x,
                if (90..110).contains(&i) {
                    f64::NAN
                } else {
                    0.5 * (0.7 * x).cos()
                },
            )
        })
        .collect();
    vec![
        ("damped sine".to_owned(), a),
        ("cosine with a gap".to_owned(), b),
    ]
}
