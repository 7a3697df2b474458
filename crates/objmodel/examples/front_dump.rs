//! Dumps what the robust classifier's front end (cleaner + rest detector) emits for each file
//! given: the noise model, the outliers, the runs of moving/rest verdicts, and every 1000th
//! item's accumulated rotation, in text (for comparing two builds).
//!
//! `cargo run --release --example front_dump -p objmodel -- OUT_DIR FILE.tum...`

use objmodel::classify::{Analyzer, Config, Item, Judged};
use std::io::Write;

fn main() {
    let mut args = std::env::args().skip(1);
    let dir = std::path::PathBuf::from(args.next().expect("OUT_DIR"));
    for path in args {
        let poses = objmodel::format::read_trajectory(std::path::Path::new(&path)).expect("file");
        let config = Config::default();
        let mut a = Analyzer::new("dump", &config, false);
        let mut front = a.take_object_front().expect("robust, no palm");
        let name = path.replace('/', "_");
        let mut w = std::io::BufWriter::new(std::fs::File::create(dir.join(name)).unwrap());
        let (mut k, mut last) = (0usize, None::<bool>);
        let mut emit = |j: Judged| match j {
            Judged::Noise(n) => writeln!(w, "noise {:?}", n).unwrap(),
            Judged::Item(i, m, r) => {
                match i {
                    Item::Outlier(index, t) => writeln!(w, "outlier {index} {t:?}").unwrap(),
                    Item::Frame(f) => {
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
