//! The 3D view in a real headless browser (Debian's `chromium`): the page of a learnt box
//! loads without errors, draws (a screenshot whose 3D canvas holds the model's colours), shows
//! the centre of mass's support and uncertainty on hover, and plays a demonstration back; a
//! script error on the page is reported on the page.
//!
//! Without chromium the browser tests are skipped with a message, unless
//! `OBJMODEL_REQUIRE_CHROMIUM=1` (as CI sets it); `OBJMODEL_CHROMIUM=PATH` names the browser.

mod model;

use model::{analytic_box, learnt_box};
use objmodel::synth::SynthNoise;
use objmodel_plot::{view_page, write_view, Known};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The browser, or None (and a message) when the test may be skipped.
fn chromium() -> Option<PathBuf> {
    let named = std::env::var_os("OBJMODEL_CHROMIUM").map(PathBuf::from);
    let found = named.or_else(|| {
        ["chromium", "chromium-browser"].iter().find_map(|name| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths)
                    .map(|d| d.join(name))
                    .find(|p| p.is_file())
            })
        })
    });
    if found.is_none() {
        assert!(
            std::env::var("OBJMODEL_REQUIRE_CHROMIUM").as_deref() != Ok("1"),
            "OBJMODEL_REQUIRE_CHROMIUM=1 but no chromium on PATH (apt-get install -y \
             --no-install-recommends chromium, or set OBJMODEL_CHROMIUM)"
        );
        eprintln!(
            "SKIPPED: no chromium on PATH; the 3D view's browser test did not run (install \
             Debian's chromium, or set OBJMODEL_REQUIRE_CHROMIUM=1 to make this a failure)"
        );
    }
    found
}

/// Runs the browser headless on `url` with `extra` arguments (a new empty profile, no
/// network, software WebGL); returns its standard output and error. At most 90 s.
fn browse(browser: &Path, url: &str, extra: &[&str]) -> (String, String) {
    let profile = tempfile::tempdir().unwrap();
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--enable-unsafe-swiftshader",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--window-size=1200,900",
            "--enable-logging=stderr",
            "--v=1",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(extra)
        .arg(url)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("{}: {e}", browser.display()));
    let (mut out, mut err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut err, &mut s).ok();
        s
    });
    let mut stdout = String::new();
    let start = Instant::now();
    let reader_out = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut out, &mut s).ok();
        s
    });
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > Duration::from_secs(90) {
            child.kill().ok();
            child.wait().ok();
            panic!("{} did not finish within 90 s", browser.display());
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    stdout += &reader_out.join().unwrap();
    (stdout, reader.join().unwrap())
}

/// The value of attribute `name` of the element with id `id` in `dom`.
fn attr<'a>(dom: &'a str, id: &str, name: &str) -> Option<&'a str> {
    let at = dom.find(&format!("id=\"{id}\""))?;
    let start = dom[..at].rfind('<')?;
    let tag = &dom[start..start + dom[start..].find('>')?];
    let key = format!(" {name}=\"");
    let v = tag.find(&key)? + key.len();
    Some(&tag[v..v + tag[v..].find('"')?])
}

/// The text of the element with id `id`.
fn text<'a>(dom: &'a str, id: &str) -> &'a str {
    let at = dom.find(&format!("id=\"{id}\"")).unwrap();
    let open = at + dom[at..].find('>').unwrap() + 1;
    &dom[open..open + dom[open..].find('<').unwrap()]
}

/// Console messages that are errors, from the browser's log.
fn console_errors(log: &str) -> Vec<&str> {
    log.lines()
        .filter(|l| l.contains("CONSOLE") && (l.contains("Uncaught") || l.contains("rror")))
        .collect()
}

#[test]
fn the_page_is_self_contained() {
    let (_, tree, demos) = learnt_box(5, &SynthNoise::REAL);
    let page = view_page(&tree, "box", &demos);
    assert!(
        !page.contains("<script src") && !page.contains("<link"),
        "loads a file"
    );
    for load in [
        "src=\"http",
        "href=\"http",
        "url(http",
        "import(\"http",
        "fetch(",
    ] {
        assert!(
            !page.contains(load),
            "the page loads from the network: {load}"
        );
    }
    assert_eq!(
        page.matches("Three.js Authors").count(),
        1,
        "three.js not inlined once"
    );
    eprintln!("page: {} bytes, {} demonstrations", page.len(), demos.len());
}

#[test]
fn the_page_draws_the_model_in_a_browser() {
    let Some(browser) = chromium() else { return };
    let (_, tree, demos) = learnt_box(4, &SynthNoise::REAL);
    let dir = tempfile::tempdir().unwrap();
    let page = write_view(&tree, "learnt box", &demos, &dir.path().join("view.html")).unwrap();
    let url = format!("file://{}#selftest", page.display());
    let t0 = Instant::now();
    let (dom, log) = browse(&browser, &url, &["--dump-dom"]);
    let dumped = t0.elapsed();
    assert_eq!(
        text(&dom, "objmodel-errors"),
        "",
        "the page reported errors"
    );
    assert_eq!(console_errors(&log), Vec::<&str>::new(), "console errors");
    assert_eq!(
        attr(&dom, "objmodel-status", "data-state"),
        Some("drawn"),
        "status: {}",
        text(&dom, "objmodel-status")
    );
    // Hovering over the CoM shows the CoM, with its support and uncertainty.
    assert_eq!(attr(&dom, "objmodel-status", "data-picked"), Some("com"));
    let tip = text(&dom, "objmodel-tip");
    assert!(
        tip.contains("centre of mass") && tip.contains("pendulum"),
        "tip: {tip}"
    );
    assert_eq!(attr(&dom, "objmodel-status", "data-playback"), Some("ok"));

    // The screenshot's 3D canvas holds the model: its faces and learnt edges (seen), the
    // shape's other edges and vertices (inferred).
    let shot = dir.path().join("shot.png");
    let t1 = Instant::now();
    browse(
        &browser,
        &url,
        &[&format!("--screenshot={}", shot.display())],
    );
    let shot_time = t1.elapsed();
    let rect: Vec<usize> = attr(&dom, "objmodel-status", "data-canvas")
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let decoder = png::Decoder::new(std::fs::File::open(&shot).expect("a screenshot"));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let (mut drawn, mut seen, mut inferred, mut total) = (0, 0, 0, 0);
    let near =
        |p: &[u8], c: [u8; 3]| (0..3).all(|k| (i32::from(p[k]) - i32::from(c[k])).abs() < 40);
    for y in rect[1]..(rect[1] + rect[3]).min(info.height as usize) {
        for x in rect[0]..(rect[0] + rect[2]).min(info.width as usize) {
            let i = (y * info.width as usize + x) * channels;
            let p = &buf[i..i + 3];
            total += 1;
            drawn += usize::from(p != [255, 255, 255]);
            seen += usize::from(near(p, Known::Seen.rgb()));
            inferred += usize::from(near(p, Known::Inferred.rgb()));
        }
    }
    eprintln!(
        "canvas {rect:?}: {drawn} of {total} pixels drawn, {seen} seen-blue, {inferred} \
         inferred-orange; browser {:.1} s (DOM) + {:.1} s (screenshot)",
        dumped.as_secs_f64(),
        shot_time.as_secs_f64()
    );
    if let Some(keep) = std::env::var_os("OBJMODEL_PLOT_KEEP").map(PathBuf::from) {
        std::fs::create_dir_all(&keep).unwrap();
        std::fs::copy(&page, keep.join("view.html")).unwrap();
        std::fs::copy(&shot, keep.join("view.png")).unwrap();
    }
    assert!(drawn * 20 > total, "the canvas is nearly blank");
    assert!(seen > 500, "no learnt edges on the screen");
    assert!(inferred > 50, "no vertices or inferred edges on the screen");
}

/// A model without a closed shape (a face's offset unknown): its unknown directions and
/// loose faces draw without error too.
#[test]
fn an_open_model_draws_in_a_browser() {
    let Some(browser) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let page = write_view(
        &analytic_box(false),
        "open",
        &[],
        &dir.path().join("open.html"),
    )
    .unwrap();
    let (dom, log) = browse(
        &browser,
        &format!("file://{}#selftest", page.display()),
        &["--dump-dom"],
    );
    assert_eq!(
        text(&dom, "objmodel-errors"),
        "",
        "the page reported errors"
    );
    assert_eq!(console_errors(&log), Vec::<&str>::new(), "console errors");
    assert_eq!(attr(&dom, "objmodel-status", "data-state"), Some("drawn"));
    assert_eq!(attr(&dom, "objmodel-status", "data-picked"), Some("com"));
    let notes = &dom[dom.find("id=\"objmodel-notes\"").unwrap()..];
    let notes = &notes[..notes.find("</div>").unwrap()];
    assert!(
        notes.contains("<p") && notes.contains("no closed shape"),
        "{notes}"
    );
}

#[test]
fn a_script_error_shows_on_the_page() {
    let Some(browser) = chromium() else { return };
    let (_, tree, _) = learnt_box(4, &SynthNoise::REAL);
    let page = view_page(&tree, "broken", &[]).replacen(
        "</body>",
        "<script>objmodelNoSuchFunction();</script></body>",
        1,
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("broken.html");
    std::fs::write(&path, page).unwrap();
    let (dom, log) = browse(
        &browser,
        &format!("file://{}", path.display()),
        &["--dump-dom"],
    );
    assert_eq!(attr(&dom, "objmodel-status", "data-state"), Some("error"));
    assert!(text(&dom, "objmodel-errors").contains("objmodelNoSuchFunction"));
    assert!(
        !console_errors(&log).is_empty(),
        "the log shows no error: {log}"
    );
}
