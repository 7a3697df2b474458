//! Dumps what the robust classifier's front end (cleaner + rest detector) emits for each file
//! given: the noise model, the outliers, the runs of moving/rest verdicts, and every 1000th
//! item's accumulated rotation, in text (for comparing two builds).
//!
//! `cargo run --release --example front_dump -p objmodel -- OUT_DIR FILE.tum...`

use objmodel::bench::{AnalyzerStages, Sample, Verdict};
use objmodel::classify::{Analyzer, Config};
use std::io::Write;

fn main() {
    let mut args = std::env::args().skip(1);
    let dir = std::path::PathBuf::from(args.next().expect("OUT_DIR"));
    for path in args {
        let poses = objmodel::format::read_trajectory(std::path::Path::new(&path)).expect("file");
        let config = Config::default();
        let mut a = Analyzer::new("dump", &config, false);
        let mut front = a.take_object_rest_test().expect("robust, no palm");
        let name = path.replace('/', "_");
        let mut w = std::io::BufWriter::new(std::fs::File::create(dir.join(name)).unwrap());
        let (mut k, mut last) = (0usize, None::<bool>);
        let mut emit = |j: Verdict| match j {
            Verdict::Noise(n) => writeln!(w, "noise {:?}", n).unwrap(),
            Verdict::Sample(i, m, r) => {
                match i {
                    Sample::Outlier(index, t) => writeln!(w, "outlier {index} {t:?}").unwrap(),
                    Sample::Frame(f) => {
                        if last != Some(m) {
                            writeln!(w, "moving={m} from {}", f.index).unwrap();
                            last = Some(m);
                        }
                        if k % 1000 == 0 {
                            writeln!(
                                w,
                                "rot {} {:?} {:?} {:?} q {:?}",
                                f.index,
                                r.x,
                                r.y,
                                r.z,
                                f.q.coords.as_slice()
                            )
                            .unwrap();
                        }
                    }
                }
                k += 1;
            }
        };
        for p in &poses {
            front.push(p, &mut emit);
        }
        front.finish(&mut emit);
        writeln!(w, "items {k}").unwrap();
    }
}
