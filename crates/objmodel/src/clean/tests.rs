//! The cleaner's tests: against a queue-based reference, and on glitches of every kind.

use super::*;

fn frame(i: usize, angle: f64) -> RawFrame {
    RawFrame {
        index: i,
        t: i as f64 / 30.0,
        q: UnitQuaternion::from_scaled_axis(Vector3::new(0.0, angle, 0.0)),
        p: Vector3::zeros(),
    }
}

fn run(frames: Vec<RawFrame>) -> Vec<(RawFrame, bool)> {
    let mut c = Cleaner::new(0.0087, 1e-3, 1e-6);
    let mut out = Vec::new();
    for f in frames {
        c.push(f, &mut |f, o| out.push((f, o)));
    }
    c.finish(&mut |f, o| out.push((f, o)));
    out
}

#[test]
fn rejects_single_flips_keeps_fast_motion_and_fixes_signs() {
    let mut frames: Vec<RawFrame> = (0..60)
        .map(|i| frame(i, 0.02 * (i as f64).powi(2) / 10.0))
        .collect();
    // A mirror-like flip at frame 20: 40 degrees about x for one frame.
    frames[20].q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.7, 0.0, 0.0));
    // Sign flips.
    for i in [5usize, 6, 33] {
        frames[i].q = UnitQuaternion::new_unchecked(-frames[i].q.into_inner());
    }
    let out = run(frames);
    assert_eq!(out.len(), 60);
    let flagged: Vec<usize> = out
        .iter()
        .filter(|(_, o)| *o)
        .map(|(f, _)| f.index)
        .collect();
    assert_eq!(flagged, vec![20]);
    for w in out.windows(2) {
        assert!(w[0].0.q.quaternion().dot(w[1].0.q.quaternion()) > 0.0 || w[0].1 || w[1].1);
    }
}

/// The cleaner as first written (a queue of frames), as a reference for the slotted one.
fn reference(frames: &[RawFrame]) -> Vec<(RawFrame, bool)> {
    let c = Cleaner::new(0.0087, 1e-3, 1e-6);
    let (mut kept_prev, mut kept) = (None::<RawFrame>, None::<RawFrame>);
    let mut buffer = std::collections::VecDeque::new();
    let mut out = Vec::new();
    let mut emit = |f: RawFrame, bad: bool, kp: &mut Option<RawFrame>, k: &mut Option<RawFrame>| {
        if !bad {
            *kp = k.replace(f);
        }
        out.push((f, bad));
    };
    for &f in frames {
        let mut f = f;
        if let Some(last) = buffer.back().or(kept.as_ref()) {
            f.q = align(f.q, &last.q);
        }
        buffer.push_back(f);
        loop {
            match kept {
                None if buffer.len() >= 3 => {
                    let bad = c.is_flip(&buffer[1], &buffer[2], &buffer[0]);
                    let first = buffer.pop_front().unwrap();
                    emit(first, bad, &mut kept_prev, &mut kept);
                }
                Some(k) if buffer.len() >= 2 => {
                    let bad = match c.verdict(&k, &buffer[1], &buffer[0]) {
                        Verdict::Keep => false,
                        Verdict::Flip => true,
                        Verdict::Suspect => {
                            // The shortest run of glitches from here, once testable.
                            let run = (2..=MAX_RUN).find(|&n| {
                                buffer.len() <= n
                                    || (0..n).all(|i| {
                                        c.verdict_exact(&k, &buffer[n], &buffer[i]) == Verdict::Flip
                                    })
                            });
                            match run {
                                Some(n) if buffer.len() <= n => break,
                                Some(n) => {
                                    for _ in 0..n {
                                        let f = buffer.pop_front().unwrap();
                                        emit(f, true, &mut kept_prev, &mut kept);
                                    }
                                    continue;
                                }
                                None => false,
                            }
                        }
                    };
                    let mut next = buffer.pop_front().unwrap();
                    if !bad {
                        next.q = align(next.q, &k.q);
                    }
                    emit(next, bad, &mut kept_prev, &mut kept);
                }
                _ => break,
            }
        }
    }
    for f in buffer {
        let bad = match (&kept_prev, &kept) {
            (Some(a), Some(b)) => c.is_flip(a, b, &f),
            _ => false,
        };
        emit(f, bad, &mut kept_prev, &mut kept);
    }
    out
}

#[test]
fn matches_the_queue_based_reference() {
    // Random walks with flips (single, consecutive, at the ends), runs of 1 to 6 wrong
    // positions, and sign changes.
    let mut seed = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x9e37_79b9_7f4a_7c15);
    let mut rnd = move || rand::Rng::random::<f64>(&mut seed);
    let mut flagged = 0;
    for n in [1usize, 2, 3, 4, 5, 8, 40, 200] {
        for _ in 0..50 {
            let (mut angle, mut p, mut glitch) = (Vector3::zeros(), Vector3::zeros(), 0);
            let frames: Vec<RawFrame> = (0..n)
                .map(|i| {
                    angle += Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 0.05;
                    p += Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 2e-3;
                    let mut f = frame(i, 0.0);
                    f.q = UnitQuaternion::from_scaled_axis(angle);
                    f.p = p;
                    if glitch == 0 && rnd() < 0.05 {
                        glitch = 1 + (rnd() * 6.0) as usize;
                    }
                    if glitch > 0 {
                        f.p.z += 0.03;
                        glitch -= 1;
                    }
                    if rnd() < 0.15 {
                        f.q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.8, 0.0, 0.0));
                    }
                    if rnd() < 0.3 {
                        f.q = UnitQuaternion::new_unchecked(-f.q.into_inner());
                    }
                    f
                })
                .collect();
            let out = run(frames.clone());
            flagged += out.iter().filter(|(_, o)| *o).count();
            assert_eq!(out, reference(&frames));
        }
    }
    assert!(flagged > 500, "{flagged}");
}

#[test]
fn rejects_two_flips_in_a_row_and_keeps_a_real_jump() {
    // A slow turn with frames 20 and 21 both flipped (the same mirror solution, 40° about
    // x), and frames 50-51 flipped by different amounts.
    let mut frames: Vec<RawFrame> = (0..80).map(|i| frame(i, 0.01 * i as f64)).collect();
    for (i, a) in [(20, 0.7), (21, 0.7), (50, 0.6), (51, 0.75)] {
        frames[i].q *= UnitQuaternion::from_scaled_axis(Vector3::new(a, 0.0, 0.0));
    }
    let out = run(frames.clone());
    let flagged: Vec<usize> = out
        .iter()
        .filter(|(_, o)| *o)
        .map(|(f, _)| f.index)
        .collect();
    assert_eq!(flagged, vec![20, 21, 50, 51]);
    assert_eq!(out, reference(&frames));
    // An impact: the orientation jumps by 40° at frame 30 and stays: nothing is rejected
    // (the first frame after the jump costs nothing either).
    let jump: Vec<RawFrame> = (0..60)
        .map(|i| {
            let mut f = frame(i, 0.01 * i as f64);
            if i >= 30 {
                f.q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.7, 0.0, 0.0));
            }
            f
        })
        .collect();
    let out = run(jump.clone());
    assert!(
        out.iter().all(|(_, o)| !o),
        "{:?}",
        out.iter().filter(|x| x.1).count()
    );
    assert_eq!(out, reference(&jump));
}

#[test]
fn rejects_a_flip_on_the_first_and_last_frame() {
    let mut frames: Vec<RawFrame> = (0..10).map(|i| frame(i, 0.01 * i as f64)).collect();
    frames[0].q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.8, 0.0, 0.0));
    frames[9].q *= UnitQuaternion::from_scaled_axis(Vector3::new(-0.8, 0.0, 0.0));
    let out = run(frames);
    let flagged: Vec<usize> = out
        .iter()
        .filter(|(_, o)| *o)
        .map(|(f, _)| f.index)
        .collect();
    assert_eq!(flagged, vec![0, 9]);
}

/// Frames of a slow slide (1 cm/s along x, turning 0.1 rad/s) with Gaussian noise of the
/// cleaner's sigmas (0.5°, 1 mm), at 30 Hz.
fn noisy_slide(n: usize, seed: u64) -> Vec<RawFrame> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let (rot, pos) = (
        Normal::new(0.0, 0.0087).unwrap(),
        Normal::new(0.0, 1e-3).unwrap(),
    );
    (0..n)
        .map(|i| {
            let t = i as f64 / 30.0;
            let mut f = frame(i, 0.1 * t);
            f.q *= UnitQuaternion::from_scaled_axis(Vector3::from_fn(|_, _| rot.sample(&mut rng)));
            f.p = Vector3::new(0.01 * t, 0.0, 0.0) + Vector3::from_fn(|_, _| pos.sample(&mut rng));
            f
        })
        .collect()
}

fn flagged(frames: Vec<RawFrame>) -> Vec<usize> {
    let out = run(frames);
    out.iter()
        .filter(|(_, o)| *o)
        .map(|(f, _)| f.index)
        .collect()
}

#[test]
fn rejects_runs_of_wrong_positions_up_to_max_run_and_keeps_a_real_jump() {
    // Runs of 1 to MAX_RUN frames whose position is 2 cm off (a misread tag, a marker
    // swap), orientation untouched, in a slow noisy slide.
    let mut frames = noisy_slide(200, 1);
    let mut expected = Vec::new();
    for (n, start) in (1..=MAX_RUN).zip([20, 60, 100, 140]) {
        for f in &mut frames[start..start + n] {
            f.p += Vector3::new(0.0, 0.014, 0.014);
            expected.push(f.index);
        }
    }
    assert_eq!(flagged(frames), expected);
    // One frame longer than a run can be: a motion the learner's models must judge (a
    // bounce of five frames is a flight they can identify); the cleaner keeps it.
    let mut frames = noisy_slide(200, 2);
    for f in &mut frames[50..51 + MAX_RUN] {
        f.p.z += 0.02;
    }
    assert_eq!(flagged(frames), Vec::<usize>::new());
    // A jump that stays (a push, an impact): nothing is rejected.
    let mut frames = noisy_slide(200, 3);
    for f in &mut frames[90..] {
        f.p.x += 0.02;
    }
    assert_eq!(flagged(frames), Vec::<usize>::new());
}

#[test]
fn rejects_runs_of_mirror_flips_up_to_max_run() {
    let mut frames = noisy_slide(200, 4);
    let mut expected = Vec::new();
    for (n, start) in (1..=MAX_RUN).zip([30, 70, 110, 150]) {
        for f in &mut frames[start..start + n] {
            f.q *= UnitQuaternion::from_scaled_axis(Vector3::new(0.7, 0.0, 0.0));
            expected.push(f.index);
        }
    }
    assert_eq!(flagged(frames), expected);
}

#[test]
fn smooth_fast_motion_with_noise_loses_no_frame() {
    // Tosses: a parabola at up to 5 m/s under gravity, spinning at up to 20 rad/s about a
    // random axis, at 30 to 240 Hz, with the cleaner's noise; and the same at rest.
    use rand::{Rng, SeedableRng};
    use rand_distr::{Distribution, Normal};
    let mut rng = rand::rngs::StdRng::seed_from_u64(5);
    let (rot, pos) = (
        Normal::new(0.0, 0.0087).unwrap(),
        Normal::new(0.0, 1e-3).unwrap(),
    );
    let mut frames_seen = 0;
    for case in 0..300 {
        let rate = [30.0, 60.0, 120.0, 240.0][case % 4];
        let speed = if case % 5 == 0 { 0.0 } else { 5.0 };
        let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)) * speed;
        let w = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)) * speed * 4.0 / 1.8;
        let g = Vector3::new(0.0, 0.0, -9.81) * (speed > 0.0) as u8 as f64;
        let frames: Vec<RawFrame> = (0..60)
            .map(|i| {
                let t = i as f64 / rate;
                let noise = Vector3::from_fn(|_, _| rot.sample(&mut rng));
                RawFrame {
                    index: i,
                    t,
                    q: UnitQuaternion::from_scaled_axis(w * t)
                        * UnitQuaternion::from_scaled_axis(noise),
                    p: v * t + g * (0.5 * t * t) + Vector3::from_fn(|_, _| pos.sample(&mut rng)),
                }
            })
            .collect();
        frames_seen += frames.len();
        assert_eq!(flagged(frames), Vec::<usize>::new(), "case {case}");
    }
    assert_eq!(frames_seen, 18_000);
}
