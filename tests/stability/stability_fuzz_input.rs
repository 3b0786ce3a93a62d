//! Stability case 9 (docs/stability.md): malformed input. The scene loader is fuzzed with
//! mutated valid scenes (lines deleted, duplicated or swapped, values and keys replaced by
//! ill-typed or out-of-range tokens, the text cut short, stray characters) and the mesh
//! loader with mutated STL and OBJ files: never a panic; every rejected scene gives an error
//! that names the file and a key; every rejected mesh an error that names the mesh file.
//! (Fixed bad inputs, one per kind of error, are `scenes/bad/*.toml`, tests/input/scenes_bad.rs.)
//!
//! CI runs 1000 mutated scenes and 256 mutated meshes; `WETBOUNCE_CASES=N cargo test --release --test
//! stability_fuzz_input -- --ignored` runs N.

use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Valid scenes to mutate: the shipped ones (but the 10,000-bead benchmarks, slow to fill), the
/// test scenes, and the annotated example's features through the column and contactor.
fn sources() -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    for dir in ["scenes", "tests/scenes"] {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                p.extension().is_some_and(|e| e == "toml")
                    && !p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("bench_"))
            })
            .collect();
        paths.sort();
        for p in paths {
            let text = std::fs::read_to_string(&p).unwrap();
            out.push((p, text));
        }
    }
    assert!(out.len() >= 7, "{} source scenes", out.len());
    out
}

/// Tokens a value or a key may be replaced with.
const TOKENS: &[&str] = &[
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-308",
    "nan",
    "inf",
    "-inf",
    "3",
    "2.5e-3",
    "\"x\"",
    "\"\"",
    "[]",
    "{}",
    "true",
    "[1.0, 2.0]",
    "[0.0, 0.0, 0.0]",
    "[1e308, 0.0, 0.0]",
    "[nan, 0.0, 0.0]",
    "\"box\"",
    "\"plane\"",
    "\"mesh\"",
    "\"cylinder\"",
    "\"annulus\"",
    "\"drop\"",
    "\"solid\"",
    "\"rk4\"",
    "\"meshes/plate.obj\"",
    "\"meshes/none.stl\"",
    "\"../Cargo.toml\"",
    "{ type = \"disk\" }",
    "4294967296",
    "9223372036854775808",
    "1e300",
    "-1e300",
    "1e155",
    "1e-300",
    "[0.0, 0.0, 1.0, 99.0]",
    "[0.0, 0.0, 1.0, 99.0, \"x\", true]",
    "[0.0, 0.0, -1e200]",
    "[1e155, 0.0, 0.0]",
    "[1e-300, 0.0, 0.0]",
    "-9223372036854775808",
    "1e3",
    "[[",
    "=",
    "\"\\u0000\"",
    "'''",
    "#",
];

#[derive(Debug, Clone)]
enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    ReplaceValue(usize, usize),
    ReplaceKey(usize, usize),
    Truncate(usize),
    Insert(usize, char),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let t = 0..TOKENS.len();
    prop_oneof![
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        4 => (any::<usize>(), t.clone()).prop_map(|(a, b)| Mutation::ReplaceValue(a, b)),
        1 => (any::<usize>(), t).prop_map(|(a, b)| Mutation::ReplaceKey(a, b)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        1 => (any::<usize>(), prop_oneof![Just('['), Just(']'), Just('"'), Just('='), Just('\n'), Just('.'), Just('é'), any::<char>()])
            .prop_map(|(a, c)| Mutation::Insert(a, c)),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let n = lines.len().max(1);
    match *m {
        Mutation::DeleteLine(i) => {
            if !lines.is_empty() {
                lines.remove(i % n);
            }
        }
        Mutation::DuplicateLine(i) => {
            if !lines.is_empty() {
                let l = lines[i % n].clone();
                lines.insert(i % n, l);
            }
        }
        Mutation::SwapLines(a, b) => {
            if !lines.is_empty() {
                lines.swap(a % n, b % n);
            }
        }
        Mutation::ReplaceValue(i, t) | Mutation::ReplaceKey(i, t) => {
            // Among the lines with a `key = value`.
            let kv: Vec<usize> =
                (0..lines.len()).filter(|&k| lines[k].contains('=') && !lines[k].starts_with('#')).collect();
            if !kv.is_empty() {
                let k = kv[i % kv.len()];
                let (key, value) = lines[k].split_once('=').unwrap();
                lines[k] = if matches!(m, Mutation::ReplaceValue(..)) {
                    format!("{key}= {}", TOKENS[t])
                } else {
                    format!("{} ={value}", TOKENS[t])
                };
            }
        }
        Mutation::Truncate(at) => {
            let s = lines.join("\n");
            let mut cut = at % (s.len() + 1);
            while !s.is_char_boundary(cut) {
                cut -= 1;
            }
            return s[..cut].to_string();
        }
        Mutation::Insert(at, c) => {
            let mut s = lines.join("\n");
            let mut at = at % (s.len() + 1);
            while !s.is_char_boundary(at) {
                at -= 1;
            }
            s.insert(at, c);
            return s;
        }
    }
    lines.join("\n")
}

fn check_scene(
    source: usize,
    mutations: &[Mutation],
    sources: &[(PathBuf, String)],
) -> Result<(), TestCaseError> {
    let (path, text) = &sources[source % sources.len()];
    let mut text = text.clone();
    for m in mutations {
        text = apply(&text, m);
    }
    let loaded = catch_unwind(AssertUnwindSafe(|| wetbounce::Scene::from_str(&text, path)));
    let Ok(result) = loaded else {
        return Err(TestCaseError::fail(format!("panicked on {}:\n{text}", path.display())));
    };
    if let Err(e) = result {
        let message = e.to_string();
        let file = path.display().to_string();
        prop_assert!(message.starts_with(&format!("{file}: ")), "does not name the file: {message}");
        prop_assert!(!e.key().trim().is_empty(), "does not name a key: {message}");
        prop_assert!(message.len() > file.len() + e.key().len() + 4, "no message: {message}");
        prop_assert!(!has_long_number(&message), "a number printed in full: {message}");
    }
    Ok(())
}

fn run_scenes(cases: u32) {
    let sources = sources();
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let strategy = (any::<usize>(), prop::collection::vec(mutation(), 1..4));
    let start = std::time::Instant::now();
    let result = runner.run(&strategy, |(s, ms)| check_scene(s, &ms, &sources));
    println!("scene loader: {cases} cases in {:.1} s", start.elapsed().as_secs_f64());
    result.unwrap();
}

/// Mesh files to mutate, as bytes.
fn mesh_sources() -> Vec<(&'static str, Vec<u8>)> {
    ["plate_ascii.stl", "plate_binary.stl", "plate.obj"]
        .into_iter()
        .map(|f| (f, std::fs::read(root().join("scenes/meshes").join(f)).unwrap()))
        .collect()
}

fn check_mesh(
    source: usize,
    edits: &[(usize, u8)],
    cut: Option<usize>,
    scale: f64,
    dir: &Path,
) -> Result<(), TestCaseError> {
    let sources = mesh_sources();
    let (name, bytes) = &sources[source % sources.len()];
    let mut bytes = bytes.clone();
    for &(at, b) in edits {
        let n = bytes.len();
        if n > 0 {
            bytes[at % n] = b;
        }
    }
    if let Some(c) = cut {
        bytes.truncate(c % (bytes.len() + 1));
    }
    let path = dir.join(name);
    std::fs::write(&path, &bytes).unwrap();
    let loaded =
        catch_unwind(AssertUnwindSafe(|| wetbounce::walls::load_mesh(&path, scale, glam::DVec3::ZERO)));
    let Ok(result) = loaded else {
        return Err(TestCaseError::fail(format!("panicked on a mutated {name} (scale {scale})")));
    };
    match result {
        Err(e) => {
            let message = e.to_string();
            prop_assert!(
                message.contains(&path.display().to_string()),
                "does not name the mesh file: {message}"
            );
        }
        Ok(mesh) => {
            // Accepted: every vertex finite, some triangles.
            prop_assert!(mesh.mesh.num_triangles() > 0);
            prop_assert!(mesh.mesh.vertices().iter().all(|v| v.is_finite()));
        }
    }
    Ok(())
}

fn run_meshes(cases: u32) {
    let dir = tempfile::tempdir().unwrap();
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    // Bytes set to values that matter: digits, signs, separators, NaN-making exponents, 0xff.
    let byte = prop_oneof![
        Just(b'9'),
        Just(b'-'),
        Just(b' '),
        Just(b'\n'),
        Just(b'e'),
        Just(b'/'),
        Just(0xffu8),
        Just(0u8),
        any::<u8>()
    ];
    let strategy = (
        any::<usize>(),
        prop::collection::vec((any::<usize>(), byte), 0..6),
        proptest::option::of(any::<usize>()),
        prop_oneof![Just(1.0), Just(1e300), Just(1e-300), 1e-3f64..1e3],
    );
    let start = std::time::Instant::now();
    let result =
        runner.run(&strategy, |(s, edits, cut, scale)| check_mesh(s, &edits, cut, scale, dir.path()));
    println!("mesh loader: {cases} cases in {:.1} s", start.elapsed().as_secs_f64());
    result.unwrap();
}

#[test]
fn mutated_scenes_never_panic_and_every_error_names_the_file_and_a_key() {
    run_scenes(1000);
}

#[test]
fn mutated_mesh_files_never_panic_and_every_error_names_the_mesh_file() {
    run_meshes(256);
}

#[test]
fn mesh_scaled_beyond_the_largest_float_is_an_error_naming_the_scale() {
    let path = root().join("scenes/meshes/plate.obj");
    let e = wetbounce::walls::load_mesh(&path, 1e308, glam::DVec3::ZERO).expect_err("overflows");
    assert!(e.to_string().contains("once scaled by 1e308"), "{e}");
}

/// The long run: `WETBOUNCE_CASES` cases of each (default 10⁵).
#[test]
#[ignore]
fn long_run_of_mutated_inputs() {
    let cases: u32 = std::env::var("WETBOUNCE_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(100_000);
    run_scenes(cases);
    run_meshes(cases);
    run_magnitudes(cases);
}

// ---- Classes of the adversarial findings of issue 13 (docs/stability.md) ----------------------

/// Every `key = [a, b, c]` of three numbers in `text`: (byte range of the brackets, key name).
fn vector_literals(text: &str) -> Vec<(std::ops::Range<usize>, String)> {
    let mut out = Vec::new();
    let mut line_start = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split('#').next().unwrap_or("");
        let mut from = 0;
        while let Some(at) = code[from..].find("= [") {
            let open = from + at + 2;
            let Some(len) = code[open..].find(']') else { break };
            let close = open + len + 1;
            let inner = &code[open + 1..close - 1];
            let key: String = code[..from + at]
                .trim_end()
                .chars()
                .rev()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect();
            let numbers = inner.split(',').filter(|t| t.trim().parse::<f64>().is_ok()).count();
            if !inner.contains('[') && numbers == 3 && inner.split(',').count() == 3 && !key.is_empty() {
                out.push((line_start + open..line_start + close, key));
            }
            from = close;
        }
        line_start += line.len();
    }
    out
}

/// What a vector may be replaced with that is not three numbers, and the message's detail.
const NOT_THREE_NUMBERS: &[(&str, &str)] = &[
    ("[]", "got 0 values"),
    ("[1.0]", "got 1 value"),
    ("[0.0, 1.0]", "got 2 values"),
    ("[0.0, 0.0, 1.0, 99.0]", "got 4 values"),
    ("[0.0, 0.0, 1.0, 99.0, 5]", "got 5 values"),
    ("[0.0, 0.0, 1.0, 99.0, \"x\", true]", "got 6 values"),
    ("[0.0, \"x\", 1.0]", "component 1 is a string"),
    ("[true, 0.0, 1.0]", "component 0 is a boolean"),
    ("[0.0, 0.0, [1.0]]", "component 2 is an array"),
    ("[0.0, {}, 1.0]", "component 1 is a table"),
    ("[0.0, 0.0, 1979-05-27]", "component 2 is a table or a date"),
];

/// Class of finding 6: every 3-vector key of every valid scene, given anything but three
/// numbers (too few, too many, a string, a boolean, an array, a table, a date), is refused with
/// an error naming that key and saying what was given — never truncated, never accepted.
#[test]
fn every_vector_key_given_anything_but_three_numbers_is_refused_naming_the_key() {
    let mut checked = 0;
    for (path, text) in sources() {
        for (range, key) in vector_literals(&text) {
            for (replacement, detail) in NOT_THREE_NUMBERS {
                let mutated = format!("{}{replacement}{}", &text[..range.start], &text[range.end..]);
                let e = match wetbounce::Scene::from_str(&mutated, &path) {
                    Ok(_) => panic!("{}: {key} = {replacement} accepted", path.display()),
                    Err(e) => e,
                };
                let message = e.to_string();
                assert!(
                    e.key() == key || e.key().ends_with(&format!(".{key}")),
                    "{}: {key} = {replacement}: the error names {}: {message}",
                    path.display(),
                    e.key()
                );
                assert!(
                    message.contains("must be 3 numbers [x, y, z]") && message.contains(detail),
                    "{}: {key} = {replacement}: {message}",
                    path.display()
                );
                checked += 1;
            }
        }
    }
    // The sources hold dozens of vectors (positions, normals, corners, gravity, flows, regions).
    assert!(checked >= 40 * NOT_THREE_NUMBERS.len(), "only {checked} cases");
}

/// Class of finding 7 (overflow in directions): every direction of every valid scene (a normal,
/// an axis) multiplied by 2^k, k from -1000 to 1000, gives the very same scene — never a zero
/// normal, a flow switched off, or an error blaming another key. (Powers of two scale exactly,
/// so the scenes must be equal bit for bit; `src/scene/error.rs` checks powers of ten.)
#[test]
fn every_direction_scaled_by_any_power_of_two_gives_the_same_scene() {
    let mut checked = 0;
    for (path, text) in sources() {
        let Ok(original) = wetbounce::Scene::from_str(&text, &path) else { continue };
        let shown = |s: &wetbounce::Scene| format!("{:?}{:?}", s.setup, s.particles);
        let reference = shown(&original);
        for (range, key) in vector_literals(&text).into_iter().filter(|(_, k)| k == "normal" || k == "axis") {
            let v: Vec<f64> =
                text[range.start + 1..range.end - 1].split(',').map(|t| t.trim().parse().unwrap()).collect();
            for k in [-1000, -600, -300, -1, 1, 300, 600, 1000] {
                let f = 2f64.powi(k);
                let scaled = format!("[{:e}, {:e}, {:e}]", v[0] * f, v[1] * f, v[2] * f);
                let mutated = format!("{}{scaled}{}", &text[..range.start], &text[range.end..]);
                let scene = wetbounce::Scene::from_str(&mutated, &path)
                    .unwrap_or_else(|e| panic!("{}: {key} = {scaled}: {e}", path.display()));
                assert!(shown(&scene) == reference, "{}: {key} = {scaled} changed the scene", path.display());
                checked += 1;
            }
        }
    }
    assert!(checked >= 8 * 8, "only {checked} cases");
}

/// Byte ranges of the float literals of `text` (`2.5e-3`, `-9.81`, `0.0`: a digit and a `.` or
/// an exponent), as values of keys or components of arrays, outside comments.
fn float_literals(text: &str) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let mut line_start = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split('#').next().unwrap_or("");
        let b = code.as_bytes();
        let mut i = 0;
        while i < b.len() {
            let starts = (b[i].is_ascii_digit() || b[i] == b'-' || b[i] == b'+')
                && i > 0
                && matches!(b[i - 1], b' ' | b'[' | b'=' | b',');
            if !starts {
                i += 1;
                continue;
            }
            let end = (i..b.len())
                .find(|&j| !(b[j].is_ascii_alphanumeric() || matches!(b[j], b'.' | b'-' | b'+' | b'_')))
                .unwrap_or(b.len());
            let token = &code[i..end];
            let ends_well = end == b.len() || matches!(b[end], b' ' | b']' | b',' | b'}' | b'\n' | b'\r');
            if ends_well && token.contains(['.', 'e', 'E']) && token.parse::<f64>().is_ok() {
                out.push(line_start + i..line_start + end);
            }
            i = end.max(i + 1);
        }
        line_start += line.len();
    }
    out
}

/// Class of finding 7: any float of any valid scene replaced by a value of any magnitude
/// (±1e-320 to ±1e308) is either refused — with an error naming the file and a key, in a
/// message without a 20-digit number — or accepted, and then the scene runs three steps
/// without a particle going non-finite (what a diameter of 1e-300, a density of 1e300 or a
/// speed of 1e155 did).
fn check_magnitude(
    source: usize,
    which: usize,
    mantissa: f64,
    exponent: i32,
    sources: &[(PathBuf, String)],
    accepted: &std::cell::Cell<usize>,
) -> Result<(), TestCaseError> {
    let (path, text) = &sources[source % sources.len()];
    let literals = float_literals(text);
    let range = literals[which % literals.len()].clone();
    let value = mantissa * 10f64.powi(exponent);
    let mutated = format!("{}{value:e}{}", &text[..range.start], &text[range.end..]);
    let shown = || format!("{}: {} replaced by {value:e}", path.display(), &text[range.clone()]);
    let loaded = catch_unwind(AssertUnwindSafe(|| wetbounce::Scene::from_str(&mutated, path)));
    let Ok(result) = loaded else { return Err(TestCaseError::fail(format!("panicked: {}", shown()))) };
    let scene = match result {
        Err(e) => {
            let message = e.to_string();
            prop_assert!(!e.key().trim().is_empty(), "{}: no key: {message}", shown());
            prop_assert!(!has_long_number(&message), "{}: a long number: {message}", shown());
            return Ok(());
        }
        Ok(scene) => scene,
    };
    accepted.set(accepted.get() + 1);
    let mut sim = scene.simulation();
    let t = (3.0 * sim.setup.dt).min(scene.duration);
    let stepped = catch_unwind(AssertUnwindSafe(|| sim.advance_to(t)));
    prop_assert!(stepped.is_ok(), "{}: the step panicked", shown());
    prop_assert!(
        sim.record.lost.is_empty(),
        "{}: {} particles went non-finite",
        shown(),
        sim.record.lost.len()
    );
    let p = &sim.world.particles;
    prop_assert!((0..p.len()).all(|i| p.pos[i].is_finite() && p.vel[i].is_finite()), "{}", shown());
    Ok(())
}

/// Whether `message` holds a run of more than 20 digits (a number printed in full).
fn has_long_number(message: &str) -> bool {
    let mut run = 0;
    message.chars().any(|c| {
        run = if c.is_ascii_digit() { run + 1 } else { 0 };
        run > 20
    })
}

fn run_magnitudes(cases: u32) {
    let sources = sources();
    // How many mutated scenes were accepted (and stepped).
    let accepted = std::cell::Cell::new(0usize);
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let sign = prop_oneof![Just(1.0), Just(-1.0)];
    let strategy =
        (any::<usize>(), any::<usize>(), (sign, 1.0f64..10.0).prop_map(|(s, m)| s * m), -320i32..308);
    let start = std::time::Instant::now();
    runner.run(&strategy, |(s, which, m, e)| check_magnitude(s, which, m, e, &sources, &accepted)).unwrap();
    // Most magnitudes are refused; enough must be accepted for the stepping half to count.
    let accepted = accepted.get();
    println!(
        "any float of any magnitude: {cases} cases, {accepted} accepted and stepped, in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert!(accepted as u32 >= cases / 10, "only {accepted} of {cases} accepted");
}

#[test]
fn any_float_of_any_magnitude_is_refused_with_a_short_message_or_steps_finitely() {
    run_magnitudes(400);
}

/// Class of finding 8 (absurd runs): for any duration, output interval and time step in the
/// range of times, the scene is refused for its run length exactly when it asks for more than
/// 10⁷ frames or 10¹⁰ steps, the message saying the count; with `allow_long_run` never.
#[test]
fn run_length_is_refused_exactly_beyond_the_frame_and_step_limits() {
    use wetbounce::scene::{LoadOptions, MAX_FRAMES, MAX_STEPS};
    let path = root().join("scenes/glass_bead.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut runner = TestRunner::new(Config { cases: 300, failure_persistence: None, ..Config::default() });
    let exponent = -12.0f64..9.0;
    let strategy = (exponent.clone(), exponent.clone(), exponent);
    runner
        .run(&strategy, |(d, o, h)| {
            let (duration, interval, dt) = (10f64.powf(d), 10f64.powf(o), 10f64.powf(h));
            let mutated = text
                .replace("dt = 2e-4 ", &format!("dt = {dt:e} "))
                .replace("duration = 1.0 ", &format!("duration = {duration:e} "))
                .replace("output_interval = 1e-3 ", &format!("output_interval = {interval:e} "))
                .replace("integrator = \"rk2\"", "integrator = \"exponential\"");
            prop_assert!(mutated != text);
            let too_long = duration / interval > MAX_FRAMES || duration / dt > MAX_STEPS;
            match wetbounce::Scene::from_str(&mutated, &path) {
                Ok(_) => prop_assert!(!too_long, "{duration:e} / {interval:e} / {dt:e} accepted"),
                Err(e) => {
                    let message = e.to_string();
                    let about_length =
                        message.contains(" frames, more than") || message.contains(" steps, more than");
                    prop_assert_eq!(about_length, too_long, "{}", message);
                }
            }
            let allowed = wetbounce::Scene::from_str_with(
                &mutated,
                &path,
                LoadOptions { allow_long_run: true, ..Default::default() },
            );
            if let Err(e) = allowed {
                prop_assert!(!e.to_string().contains("more than the 1e"), "{e}");
            }
            Ok(())
        })
        .unwrap();
}

/// A scene of one wall (`wall`, a TOML `[[walls]]` body) and `extra` tables, in vacuum.
fn room_scene(wall: &str, extra: &str) -> String {
    format!(
        "[simulation]\ndt = 1e-4\nduration = 0.01\noutput_interval = 1e-3\n\
         [fluid]\ndensity = 0.0\nviscosity = 0.0\n\
         [[kinds]]\nname = \"glass\"\ntype = \"solid\"\ndensity = 2500.0\nyoungs_modulus = 6e10\npoisson_ratio = 0.23\n\
         [[walls]]\nname = \"w\"\n{wall}\n{extra}"
    )
}

/// The fraction of `n` seeded uniform points of the box `[lo, hi]` where a sphere of radius `r`
/// is clear of `walls` (gap ≥ 0, as at run time).
fn clear_fraction(
    walls: &[wetbounce::walls::Wall],
    lo: glam::DVec3,
    hi: glam::DVec3,
    r: f64,
    n: usize,
) -> f64 {
    use rand::{Rng, SeedableRng};
    use wetbounce::walls::Surface;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let clear = (0..n)
        .filter(|_| {
            let x = lo + (hi - lo) * glam::DVec3::new(rng.random(), rng.random(), rng.random());
            walls.iter().all(|w| w.shape.gap(x, r).gap >= 0.0)
        })
        .count();
    clear as f64 / n as f64
}

/// Class of findings 8 and 10 (no room): for random walls (a floor, a tank, an obstacle, a
/// column), random box regions and random diameters, an injector or a one-particle random fill
/// refused for want of room really has (almost) none — fewer than 2 % of 20,000 uniform points
/// of the region leave the particle clear — and one refused because no point of its region is
/// clear has almost no point clear even for a point particle. (Accepted ones found room at a point of the sample, which
/// may be a spot of no volume — a region that only touches the free space — so that direction
/// is not asserted.)
#[test]
fn injector_or_fill_refused_for_room_has_none_by_brute_force() {
    let mut runner = TestRunner::new(Config { cases: 150, failure_persistence: None, ..Config::default() });
    let size = 1e-3f64..0.05;
    let corner = (-0.05f64..0.05, -0.05f64..0.05, -0.05f64..0.05);
    let strategy = (0..4usize, size.clone(), size.clone(), corner.clone(), corner, size, any::<bool>());
    let path = root().join("scenes/room.toml");
    let refused = std::cell::Cell::new(0usize);
    runner
        .run(&strategy, |(shape, a, b, c0, c1, d, injector)| {
            let wall = match shape {
                0 => "type = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]".to_string(),
                1 => format!("type = \"box\"\nmin = [{:e}, {:e}, 0.0]\nmax = [{a:e}, {b:e}, {:e}]\ninside = true", -a, -b, a + b),
                2 => format!("type = \"box\"\nmin = [{:e}, {:e}, {:e}]\nmax = [{a:e}, {b:e}, {a:e}]\ninside = false", -a, -b, -a),
                _ => format!("type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\naxis = [0.0, 0.0, 1.0]\nradius = {a:e}"),
            };
            let lo = glam::DVec3::new(c0.0.min(c1.0), c0.1.min(c1.1), c0.2.min(c1.2));
            let hi = glam::DVec3::new(c0.0.max(c1.0), c0.1.max(c1.1), c0.2.max(c1.2)) + 1.01 * d;
            let region = format!("min = [{:e}, {:e}, {:e}]\nmax = [{:e}, {:e}, {:e}]", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
            let extra = if injector {
                format!(
                    "[[injectors]]\nkind = \"glass\"\nrate = 10.0\nseed = 1\nregion = {{ type = \"box\", {} }}\n\
                     diameter = {{ distribution = \"fixed\", value = {d:e} }}",
                    region.replace('\n', ", ")
                )
            } else {
                format!("[[random_fill]]\nkind = \"glass\"\ndiameter = {d:e}\n{region}\ncount = 1\nseed = 3")
            };
            let walls = wetbounce::Scene::from_str(&room_scene(&wall, ""), &path).unwrap().setup.walls;
            // Where the centres are drawn: the injector's region, the fill's shrunk by d/2.
            let (clo, chi) = if injector { (lo, hi) } else { (lo + 0.5 * d, hi - 0.5 * d) };
            let text = room_scene(&wall, &extra);
            match wetbounce::Scene::from_str(&text, &path) {
                Ok(_) => {}
                Err(e) => {
                    refused.set(refused.get() + 1);
                    let key = e.key().to_string();
                    let room = key.ends_with(".diameter") || key.ends_with(".region") || key.ends_with(".min");
                    prop_assert!(room, "refused for something else: {e}\n{text}");
                    let fits = clear_fraction(&walls, clo, chi, 0.5 * d, 20_000);
                    prop_assert!(fits < 0.02, "refused, but {:.1} % of the region has room: {e}\n{text}", 100.0 * fits);
                    if e.to_string().contains("no point of the region") {
                        let points = clear_fraction(&walls, clo, chi, 0.0, 20_000);
                        prop_assert!(points < 0.02, "blamed on the region, but {:.1} % of it is clear: {e}\n{text}", 100.0 * points);
                    }
                }
            }
            Ok(())
        })
        .unwrap();
    let refused = refused.get();
    println!("room: {refused} of 150 refused");
    assert!(refused >= 15, "only {refused} of 150 cases refused: the generator misses the class");
}

/// Class of finding 8 (impossible fills): a random fill asked for more than 64 % of its
/// region's volume is refused before any draw, naming `count` and the fraction asked for; one
/// asked for at most 25 % (1000 to 5000 particles, so that the region's boundary matters
/// little) is placed.
#[test]
fn random_fill_beyond_64_percent_is_refused_by_volume_and_one_below_25_percent_is_placed() {
    let mut runner = TestRunner::new(Config { cases: 40, failure_persistence: None, ..Config::default() });
    let fraction = prop_oneof![0.05f64..0.25, 0.65f64..20.0];
    let strategy = (1000u32..5000, 1e-4f64..1e-2, fraction, 0.5f64..2.0, 0.5f64..2.0);
    let path = root().join("scenes/fill.toml");
    runner
        .run(&strategy, |(count, d, fraction, ax, ay)| {
            // A box of aspect ax : ay : 1 whose volume makes the fraction asked for.
            let volume = count as f64 * std::f64::consts::FRAC_PI_6 * d * d * d / fraction;
            let z = (volume / (ax * ay)).cbrt();
            let size = glam::DVec3::new(ax * z, ay * z, z);
            prop_assume!(size.min_element() > 1.01 * d);
            let text = room_scene(
                "type = \"plane\"\npoint = [0.0, 0.0, -1.0]\nnormal = [0.0, 0.0, 1.0]",
                &format!(
                    "[[random_fill]]\nkind = \"glass\"\ndiameter = {d:e}\nmin = [0.0, 0.0, 0.0]\nmax = [{:e}, {:e}, {:e}]\ncount = {count}\nseed = 5",
                    size.x, size.y, size.z
                ),
            );
            let asked = count as f64 * std::f64::consts::FRAC_PI_6 * d * d * d / (size.x * size.y * size.z);
            match wetbounce::Scene::from_str(&text, &path) {
                Ok(scene) => {
                    prop_assert!(asked <= 0.64, "{:.0} % accepted", 100.0 * asked);
                    prop_assert_eq!(scene.particles.len(), count as usize);
                }
                Err(e) => {
                    prop_assert!(asked > 0.25, "{:.0} %: {}", 100.0 * asked, e);
                    if asked > 0.6401 {
                        let shown = format!("would take {:.0} % of the region's volume", 100.0 * asked);
                        prop_assert!(e.key() == "random_fill[0].count" && e.to_string().contains(&shown), "{}", e);
                    }
                }
            }
            Ok(())
        })
        .unwrap();
}

/// Class of finding 9 (overlapping initial particles): up to 40 `[[particles]]` of diameters
/// 0.1 to 10 mm (ratios up to 100), each at random in a 0.2 m cube or against an earlier one
/// in a random direction — touching, overlapping by 10⁻⁶ of the sum of radii, or that far
/// apart — followed by a random fill (in half the cases nothing overlaps on purpose, and a
/// particle that would overlap by chance is left out): the scene is refused exactly when two
/// overlap by brute force, the error naming the later particle of the first pair (in file
/// order), its earliest partner and the number of pairs; an accepted scene has no overlapping
/// pair, the fill's included.
#[test]
fn initial_particles_are_refused_exactly_when_two_overlap_naming_the_first_pair() {
    let mut runner = TestRunner::new(Config { cases: 100, failure_persistence: None, ..Config::default() });
    let one = (
        (0.0f64..0.2, 0.0f64..0.2, 0.0f64..0.2),
        -4.0f64..-2.0,
        0usize..5,
        any::<prop::sample::Index>(),
        (-1.0f64..1.0, 0.0f64..std::f64::consts::TAU),
    );
    let path = root().join("scenes/overlap.toml");
    let overlap = |(x, dx, y, dy): (glam::DVec3, f64, glam::DVec3, f64)| {
        let reach = 0.5 * (dx + dy);
        reach - (x - y).length() > 1e-9 * reach + 1e-15 * x.abs().max(y.abs()).max_element()
    };
    let (refused, accepted) = (std::cell::Cell::new(0usize), std::cell::Cell::new(0usize));
    runner
        .run(&(prop::collection::vec(one, 2..40), any::<bool>()), |(spec, may_overlap)| {
            let mut ps: Vec<(glam::DVec3, f64)> = Vec::new();
            for ((x, y, z), e, how, partner, (cos, phi)) in spec {
                // Half the cases place no particle overlapping another on purpose, and
                let how = if how == 3 && !may_overlap { 2 } else { how };
                let d = 10f64.powf(e);
                let at = match (how, ps.is_empty()) {
                    (0 | 1, _) | (_, true) => glam::DVec3::new(x, y, z),
                    _ => {
                        let (q, dq) = ps[partner.index(ps.len())];
                        let sin = (1.0 - cos * cos).sqrt();
                        let dir = glam::DVec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                        let f = [1.0, 1.0 - 1e-6, 1.0 + 1e-6][how - 2];
                        q + dir * (f * 0.5 * (dq + d))
                    }
                };
                // ... leave out a particle that would overlap one by chance.
                if may_overlap || !ps.iter().any(|&(q, dq)| overlap((q, dq, at, d))) {
                    ps.push((at, d));
                }
            }
            let mut text = room_scene("type = \"plane\"\npoint = [0.0, 0.0, -1.0]\nnormal = [0.0, 0.0, 1.0]", "");
            for (x, d) in &ps {
                text += &format!(
                    "[[particles]]\nkind = \"glass\"\ndiameter = {d:e}\nposition = [{:e}, {:e}, {:e}]\n",
                    x.x, x.y, x.z
                );
            }
            text += "[[random_fill]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [0.0, 0.0, 0.0]\nmax = [0.03, 0.03, 0.03]\ncount = 20\nseed = 9\n";
            let pairs: Vec<(usize, usize)> = (0..ps.len())
                .flat_map(|b| (0..b).map(move |a| (b, a)))
                .filter(|&(b, a)| overlap((ps[a].0, ps[a].1, ps[b].0, ps[b].1)))
                .collect();
            match wetbounce::Scene::from_str(&text, &path) {
                Ok(scene) => {
                    accepted.set(accepted.get() + 1);
                    prop_assert!(pairs.is_empty(), "{pairs:?} overlap, accepted:\n{text}");
                    let p = &scene.particles;
                    for b in 0..p.len() {
                        for a in 0..b {
                            let both = (p.pos[a], p.diameter[a], p.pos[b], p.diameter[b]);
                            prop_assert!(!overlap(both), "particles {a} and {b} overlap after loading:\n{text}");
                        }
                    }
                }
                Err(e) => {
                    refused.set(refused.get() + 1);
                    let message = e.to_string();
                    prop_assert!(!pairs.is_empty(), "no pair overlaps, refused: {message}\n{text}");
                    let (b, a) = pairs[0];
                    prop_assert_eq!(e.key(), format!("particles[{b}].position"), "{}", message);
                    let named = format!("particles[{b}] at");
                    let partner = format!("overlaps particles[{a}] at");
                    prop_assert!(message.contains(&named) && message.contains(&partner), "{}", message);
                    if pairs.len() > 1 {
                        let count = format!("{} pairs overlap in all", pairs.len());
                        prop_assert!(message.contains(&count), "{}", message);
                    }
                }
            }
            Ok(())
        })
        .unwrap();
    println!("overlap: {} refused, {} accepted", refused.get(), accepted.get());
    assert!(refused.get() >= 10 && accepted.get() >= 10, "the generator misses one side of the class");
}
