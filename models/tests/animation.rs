//! The animated view of a mechanism, in a real browser: the quick return's page, from a
//! short run of the flagship, loaded in headless Chromium (Debian's `chromium`; CI
//! installs it). It loads without a console message or an error, its stills at two
//! times differ where a link moved and are equal where nothing moves (the ground
//! pivots, drawn over the links). Without Chromium the browser tests say so and pass.
//!
//! How errors are caught: Chromium writes every console message (an uncaught
//! exception included) to stderr as a `…:CONSOLE…` line under `--enable-logging=stderr
//! --v=0`, and the page's player writes what it catches (`window.onerror`,
//! `console.error`) into its `.errors` block, which `--dump-dom` shows; a script that
//! does not even parse never sets the section's `data-ready`, which the test requires.
//!
//! `cargo test -p models --test animation -- --ignored` rewrites the README's picture,
//! `docs/quick_return_animation.png`.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use bgdsl_cli::animation::{write_page, BodyRecorder, BodyTrack, Scene, Shape, View};
use bgdsl_runtime::{Model, Simulation};
use models::catalog::flagship_solver;
use models::quick_return::QuickReturn;

/// The browser, if installed.
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|dir| ["chromium", "chromium-browser"].map(|name| dir.join(name)))
        .find(|candidate| candidate.is_file())
}

/// The quick return from 0 to `t_end` (samples every ms), its links as the spec's
/// boxes, its two ground pivots, the crank angle shown.
fn quick_return_scene(t_end: f64) -> Scene {
    let model = QuickReturn::default();
    let mut x0 = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x0);
    let times: Vec<f64> = (0..=(t_end * 1000.0).round() as usize)
        .map(|k| k as f64 * 1e-3)
        .collect();
    let angle = QuickReturn::OUTPUT_NAMES
        .iter()
        .position(|n| *n == "crank_angle")
        .unwrap();
    let mut recorder = BodyRecorder::new(QuickReturn::BODIES).with_angle(angle, "crank angle");
    let mut sim = Simulation::new(&model, flagship_solver()).unwrap();
    sim.run(0.0, &x0, &times, &mut recorder).unwrap();
    let p = model.params();
    let sizes = [p.l1, p.l2, p.l3, p.l4, p.l5];
    recorder
        .into_scene(|name| {
            let i = ["crank", "slider", "rocker", "rod", "output_slider"]
                .iter()
                .position(|n| *n == name)?;
            Some(Shape::Box { size: sizes[i] })
        })
        .with_ground(vec![[0.0, 0.0, 0.0], [0.0, -p.d, 0.0]])
}

/// A scratch folder for this test file.
fn scratch(name: &str) -> PathBuf {
    common::scratch(&format!("animation-{name}"))
}

/// The browser's window for every still and DOM dump (the same layout in both). Each
/// run also has `--no-sandbox` (CI runs as root) and `--disable-dev-shm-usage` (a
/// container's small /dev/shm), and a device scale of 1 (a CSS pixel is a pixel).
const WINDOW: &str = "--window-size=1000,800";

/// Chromium's DOM of `page` at `#t=…` after its scripts ran, and its stderr.
fn dump_dom(browser: &Path, page: &Path, t: f64) -> (String, String) {
    dump_dom_at(browser, page, &format!("t={t}"))
}

/// Chromium's DOM of `page` at `#fragment` after its scripts ran, and its stderr.
fn dump_dom_at(browser: &Path, page: &Path, fragment: &str) -> (String, String) {
    let out = Command::new(browser)
        .args([
            "--headless",
            "--disable-gpu",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--force-device-scale-factor=1",
            WINDOW,
            "--enable-logging=stderr",
            "--v=0",
            "--dump-dom",
        ])
        .arg(format!("file://{}#{fragment}", page.display()))
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A screenshot of `page` at `#t=…`, as (width, RGB rows).
fn screenshot(browser: &Path, page: &Path, t: f64, png: &Path) -> (usize, Vec<u8>) {
    screenshot_at(browser, page, &format!("t={t}"), png)
}

/// A screenshot of `page` at `#fragment`, as (width, RGB rows).
fn screenshot_at(browser: &Path, page: &Path, fragment: &str, png: &Path) -> (usize, Vec<u8>) {
    let status = Command::new(browser)
        .args([
            "--headless",
            "--disable-gpu",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--force-device-scale-factor=1",
            "--hide-scrollbars",
            WINDOW,
        ])
        .arg(format!("--screenshot={}", png.display()))
        .arg(format!("file://{}#{fragment}", page.display()))
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    let decoder = png::Decoder::new(fs::File::open(png).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let rgb = buf[..info.buffer_size()]
        .chunks(channels)
        .flat_map(|px| px[..3].to_vec())
        .collect();
    (info.width as usize, rgb)
}

/// The value of attribute `name` of the animation's `<section>` in a DOM dump, with
/// `&quot;` undone.
fn section_attribute(dom: &str, name: &str) -> Option<String> {
    let start = dom.find("<section id=\"bgdsl-animation\"")?;
    let tag = &dom[start..start + dom[start..].find('>')?];
    let key = format!(" {name}=\"");
    let from = tag.find(&key)? + key.len();
    let value = &tag[from..from + tag[from..].find('"')?];
    Some(value.replace("&quot;", "\"").replace("&amp;", "&"))
}

/// The numbers in a JSON-ish text, in order.
fn numbers(text: &str) -> Vec<f64> {
    text.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .filter_map(|s| s.parse().ok())
        .collect()
}

/// How many pixels differ between two screenshots in the square of half-width `r`
/// around page point `(x, y)`, and how many it holds.
fn differing(a: &(usize, Vec<u8>), b: &(usize, Vec<u8>), x: f64, y: f64, r: i64) -> (usize, usize) {
    let (width, height) = (a.0 as i64, (a.1.len() / 3 / a.0) as i64);
    let (cx, cy) = (x.round() as i64, y.round() as i64);
    let (mut differ, mut all) = (0, 0);
    for py in (cy - r).max(0)..=(cy + r).min(height - 1) {
        for px in (cx - r).max(0)..=(cx + r).min(width - 1) {
            let i = 3 * (py * width + px) as usize;
            all += 1;
            if a.1[i..i + 3] != b.1[i..i + 3] {
                differ += 1;
            }
        }
    }
    (differ, all)
}

/// The scene itself: the flagship moves in X0–Y0 (seen face on, Y0 up), the crank's
/// centre goes round half a crank length from the pivot at 5 rad/s, the angle shown is
/// the crank angle in degrees (90° at the start, θ0 = π/2).
#[test]
fn build_the_quick_returns_scene_from_a_run() {
    let scene = quick_return_scene(0.5);
    assert_eq!(
        scene.view,
        View::Plane {
            u: [1.0, 0.0, 0.0],
            v: [0.0, 1.0, 0.0]
        }
    );
    assert_eq!(scene.times.len(), 501);
    let crank = &scene.bodies[0];
    assert_eq!(crank.name, "crank");
    for (k, p) in crank.position.iter().enumerate().step_by(50) {
        // Half the crank (0.1 m) from the pivot, to the joints' deflection (< 1 mm).
        let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
        assert!((r - 0.1).abs() < 1e-3, "frame {k}: {r}");
    }
    let (label, degrees) = scene.angle.as_ref().unwrap();
    assert_eq!(label, "crank angle");
    assert!((degrees[0] - 90.0).abs() < 1e-9);
    // 0.5 s at 5 rad/s: 2.5 rad (143°) further, less the drive coupling's twist.
    assert!(
        (degrees[500] - (90.0 + 2.5_f64.to_degrees())).abs() < 2.0,
        "{}",
        degrees[500]
    );
}

#[test]
fn load_without_errors_and_move_the_links_between_two_stills() {
    let Some(browser) = chromium() else {
        eprintln!("SKIPPED: chromium is not installed (apt-get install chromium)");
        return;
    };
    let dir = scratch("stills");
    let page = dir.join("quick_return.html");
    write_page(
        &page,
        "The quick return mechanism",
        &quick_return_scene(0.5),
    )
    .unwrap();
    let (t_a, t_b) = (0.1, 0.4);

    let (dom_a, stderr_a) = dump_dom(&browser, &page, t_a);
    let (dom_b, stderr_b) = dump_dom(&browser, &page, t_b);
    assert_loaded_cleanly(&dom_a, &stderr_a);
    assert_loaded_cleanly(&dom_b, &stderr_b);
    // The player stopped at the frame of each time (one per ms).
    assert_eq!(
        section_attribute(&dom_a, "data-frame").as_deref(),
        Some("100")
    );
    assert_eq!(
        section_attribute(&dom_b, "data-frame").as_deref(),
        Some("400")
    );

    // Page coordinates of the crank's centre at t_a and of the two pivots.
    let canvas = numbers(&section_attribute(&dom_a, "data-canvas").unwrap());
    let centres = section_attribute(&dom_a, "data-centres").unwrap();
    let crank = numbers(&centres[centres.find("\"crank\"").unwrap()..]);
    let crank_b = {
        let c = section_attribute(&dom_b, "data-centres").unwrap();
        numbers(&c[c.find("\"crank\"").unwrap()..])
    };
    let moved = ((crank[0] - crank_b[0]).powi(2) + (crank[1] - crank_b[1]).powi(2)).sqrt();
    assert!(moved > 30.0, "the crank's centre moved {moved} px");
    let ground = numbers(&section_attribute(&dom_a, "data-ground").unwrap());
    assert_eq!(
        section_attribute(&dom_a, "data-ground"),
        section_attribute(&dom_b, "data-ground")
    );

    let still_a = screenshot(&browser, &page, t_a, &dir.join("a.png"));
    let still_b = screenshot(&browser, &page, t_b, &dir.join("b.png"));
    // Where the crank was at t_a, the picture changed.
    let (differ, all) = differing(
        &still_a,
        &still_b,
        canvas[0] + crank[0],
        canvas[1] + crank[1],
        4,
    );
    assert!(
        differ * 2 > all,
        "{differ} of {all} pixels differ at the crank"
    );
    // Inside each ground symbol (drawn over the links, below its pivot) nothing moves.
    for pivot in ground.chunks(2) {
        let (differ, all) = differing(
            &still_a,
            &still_b,
            canvas[0] + pivot[0],
            canvas[1] + pivot[1] + 8.0,
            2,
        );
        assert_eq!((differ, all), (0, 25), "at the pivot {pivot:?}");
    }
}

/// The errors a page reported: its console messages on stderr, its `.errors` block,
/// a player that never finished drawing.
fn assert_loaded_cleanly(dom: &str, stderr: &str) {
    let console: Vec<&str> = stderr.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(console.is_empty(), "console messages: {console:#?}");
    assert_eq!(section_attribute(dom, "data-ready").as_deref(), Some("1"));
    assert!(
        dom.contains("<pre class=\"errors\" hidden=\"\"></pre>"),
        "the player reported errors: {}",
        &dom[dom.find("<pre class=\"errors\"").unwrap()..][..400]
    );
}

/// A box tumbling about a tilted axis while its centre climbs a helix: no plane holds
/// it, so the page shows it in 3-D, and turning the view (`yaw` in the address, as a
/// drag does) moves it on the screen.
#[test]
fn turn_a_3d_scene_with_the_view() {
    let Some(browser) = chromium() else {
        eprintln!("SKIPPED: chromium is not installed (apt-get install chromium)");
        return;
    };
    let times: Vec<f64> = (0..=100).map(|k| 0.01 * k as f64).collect();
    let axis = [0.6_f64, 0.0, 0.8];
    let orientation = times
        .iter()
        .map(|t| {
            // Rodrigues: R = I + sin a K + (1 - cos a) K², K the axis' cross matrix.
            let (s, c) = (3.0 * t).sin_cos();
            let [x, y, z] = axis;
            let k = [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]];
            let mut r = [0.0; 9];
            for col in 0..3 {
                for row in 0..3 {
                    let k2: f64 = (0..3).map(|m| k[row][m] * k[m][col]).sum();
                    let id = if row == col { 1.0 } else { 0.0 };
                    r[3 * col + row] = id + s * k[row][col] + (1.0 - c) * k2;
                }
            }
            r
        })
        .collect();
    let position = times
        .iter()
        .map(|t| [0.3 * (4.0 * t).cos(), 0.3 * (4.0 * t).sin(), 0.2 * t])
        .collect();
    let body = BodyTrack {
        name: "tumbler".into(),
        shape: Shape::Box {
            size: [0.3, 0.1, 0.05],
        },
        position,
        orientation,
    };
    let scene = Scene::new(times, vec![body]);
    assert_eq!(scene.view, View::Orbit);
    let dir = scratch("orbit");
    let page = dir.join("tumbler.html");
    write_page(&page, "A tumbling box", &scene).unwrap();

    let (dom_0, stderr_0) = dump_dom_at(&browser, &page, "t=0.5&yaw=0");
    let (dom_1, stderr_1) = dump_dom_at(&browser, &page, "t=0.5&yaw=1.2");
    assert_loaded_cleanly(&dom_0, &stderr_0);
    assert_loaded_cleanly(&dom_1, &stderr_1);
    assert!(dom_0.contains("Drag the picture to turn it."));
    let canvas = numbers(&section_attribute(&dom_0, "data-canvas").unwrap());
    let centre_0 = numbers(&section_attribute(&dom_0, "data-centres").unwrap());
    let centre_1 = numbers(&section_attribute(&dom_1, "data-centres").unwrap());
    let moved = ((centre_0[0] - centre_1[0]).powi(2) + (centre_0[1] - centre_1[1]).powi(2)).sqrt();
    assert!(moved > 20.0, "turning the view moved the box {moved} px");

    let still_0 = screenshot_at(&browser, &page, "t=0.5&yaw=0", &dir.join("yaw0.png"));
    let again = screenshot_at(&browser, &page, "t=0.5&yaw=0", &dir.join("yaw0-again.png"));
    let still_1 = screenshot_at(&browser, &page, "t=0.5&yaw=1.2", &dir.join("yaw1.png"));
    assert_eq!(still_0, again, "the same still twice is the same picture");
    let (x, y) = (canvas[0] + centre_0[0], canvas[1] + centre_0[1]);
    let (differ, all) = differing(&still_0, &still_1, x, y, 3);
    assert!(
        differ * 2 > all,
        "{differ} of {all} pixels differ at the box"
    );
}

/// The program's run of a model with bodies has the animation in its index.html, with
/// the links as boxes, the pivots and the crank angle; a model without bodies has none.
#[test]
fn give_a_run_with_bodies_its_animation_section() {
    let dir = scratch("program");
    let run = |model: &str| {
        let out = Command::new(common::BIN)
            .args(["run", model, "--t-end", "0.05", "--no-plots", "--out"])
            .arg(dir.join(model))
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        fs::read_to_string(dir.join(model).join("index.html")).unwrap()
    };
    // The compliant flagship (its BODIES) and the rigid one (posed by its entry from
    // its crank angle): the crank starts at θ0 = π/2, its centre at (0, 0.1, 0).
    for model in ["quick_return", "quick_return_rigid"] {
        let index = run(model);
        assert_eq!(
            index.matches("<section id=\"bgdsl-animation\"").count(),
            1,
            "{model}"
        );
        assert!(
            index
                .contains("\"name\":\"crank\",\"shape\":{\"box\":[0.2,0.01,0.01]},\"p\":[0,0.1,0,"),
            "{model}"
        );
        assert!(index.contains("\"name\":\"rocker\",\"shape\":{\"box\":[0.7,0.01,0.01]}"));
        assert!(index.contains("\"angle\":{\"label\":\"crank angle\""));
        assert!(index.contains("\"ground\":[[0,0,0],[0,-0.4,0]]"));
    }
    assert!(!run("oscillator").contains("bgdsl-animation"));
}

/// Writes `docs/quick_return_animation.png`, the README's picture of the mechanism: a
/// still at t = 0.9 s (the output slider near the end of its stroke), at most 100 kB.
#[test]
#[ignore = "writes the README's picture: run with --ignored"]
fn write_the_readme_picture() {
    let browser = chromium().expect("chromium is needed for the picture");
    let dir = scratch("readme");
    let page = dir.join("quick_return.html");
    write_page(
        &page,
        "The quick return mechanism",
        &quick_return_scene(1.3),
    )
    .unwrap();
    let target = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/quick_return_animation.png");
    let status = Command::new(&browser)
        .args([
            "--headless",
            "--disable-gpu",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--force-device-scale-factor=1",
            "--hide-scrollbars",
            "--window-size=720,640",
        ])
        .arg(format!("--screenshot={}", target.display()))
        .arg(format!("file://{}#t=0.9", page.display()))
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    let size = fs::metadata(&target).unwrap().len();
    assert!(size < 100_000, "{size} bytes");
}
