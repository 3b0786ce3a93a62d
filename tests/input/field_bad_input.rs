//! The field reader's bad input (issue 25, points 5–9): truncated files, sizes that lie, wrong
//! arrays, device files, recursion and odd encodings are refused with an error that names the
//! file, never a panic, never an abort (an allocation of what a few bytes declare), never a
//! loop without end. Each finding has its regression test; the class tests go over a corpus
//! (every committed fixture cut at many offsets, extents and block tables that lie, arrays of
//! every wrong kind, every device in every role) and over random variants (proptest).
//!
//! A refusal must come from the reader's own checks: an error of the last resort (a panic
//! inside vtkio, caught) would mean that some input reached vtkio unvetted.

use crate::common;
use base64::Engine;
use base64::engine::general_purpose::STANDARD as B64;
use proptest::prelude::*;
use std::io::Write;
use std::path::{Path, PathBuf};
use wetbounce::Scene;
use wetbounce::fluid::field::read::{Request, load};

/// The error of the last resort: vtkio panicked and the panic was caught.
const LAST_RESORT: &str = "the VTK reader (vtkio) failed on it";

use common::field_scene as scene;

fn field(file: &str) -> String {
    format!(r#"{{ type = "field", file = "{file}" }}"#)
}

/// The message of the scene in `dir` with flow `flow`, which must be refused.
fn refused(dir: &Path, flow: &str) -> String {
    match Scene::from_str(&scene(flow), &dir.join("scene.toml")) {
        Ok(_) => panic!("accepted: {flow}"),
        Err(e) => e.to_string(),
    }
}

/// Reads `path` as a field: `None` if it is read, else the error, which must name the file and
/// not be the last resort.
fn read(path: &Path) -> Option<String> {
    match load(path, Request { array: None, data: None, axisymmetric: false }) {
        Ok(_) => None,
        Err(e) => {
            let text = e.to_string();
            let name = path.file_name().unwrap().to_string_lossy();
            assert!(text.contains(&*name), "the error does not name the file: {text}");
            assert!(!text.contains(LAST_RESORT), "vtkio panicked on an input that was not vetted: {text}");
            Some(text)
        }
    }
}

fn refused_file(path: &Path) -> String {
    read(path).unwrap_or_else(|| panic!("{} accepted", path.display()))
}

fn says(text: &str, parts: &[&str]) {
    for p in parts {
        assert!(text.contains(p), "{text:?} should say {p:?}");
    }
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fields").join(name)
}

const HEAD: &str = r#"<?xml version="1.0"?>"#;

/// Image data of extent `whole`, spacing `spacing`, with the point data `arrays`.
fn vti(whole: &str, spacing: &str, arrays: &str, root_extra: &str) -> String {
    format!(
        r#"{HEAD}
<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" header_type="UInt32"{root_extra}>
<ImageData WholeExtent="{whole}" Origin="0 0 0" Spacing="{spacing}">
<Piece Extent="{whole}">
<PointData>
{arrays}
</PointData>
</Piece>
</ImageData>
</VTKFile>
"#
    )
}

/// An ASCII array of `n` values.
fn ascii(name: &str, ty: &str, comps: u32, n: usize) -> String {
    let values: Vec<String> = (0..n).map(|i| format!("{}", (i % 7) as f64 * 0.25)).collect();
    format!(
        r#"<DataArray type="{ty}" Name="{name}" NumberOfComponents="{comps}" format="ascii">{}</DataArray>"#,
        values.join(" ")
    )
}

/// The good image of 3 × 3 × 3 points.
fn good_vti() -> String {
    vti("0 2 0 2 0 2", "0.5 0.5 0.5", &ascii("U", "Float64", 3, 81), "")
}

/// An inline binary array of `bytes` (uncompressed): the size word, then the data.
fn binary(name: &str, ty: &str, comps: u32, declared: u32, bytes: &[u8]) -> String {
    let mut all = declared.to_le_bytes().to_vec();
    all.extend_from_slice(bytes);
    format!(
        r#"<DataArray type="{ty}" Name="{name}" NumberOfComponents="{comps}" format="binary">{}</DataArray>"#,
        B64.encode(all)
    )
}

fn zlib(raw: &[u8], level: u32) -> Vec<u8> {
    let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::new(level));
    e.write_all(raw).unwrap();
    e.finish().unwrap()
}

/// A compressed inline array: the block table `[nb][nu][np][nc…]` and the blocks, each base64
/// on its own, as VTK writes them.
fn compressed(name: &str, comps: u32, table: &[u32], data: &[u8]) -> String {
    let header: Vec<u8> = table.iter().flat_map(|w| w.to_le_bytes()).collect();
    format!(
        r#"<DataArray type="Float32" Name="{name}" NumberOfComponents="{comps}" format="binary">{}{}</DataArray>"#,
        B64.encode(header),
        B64.encode(data)
    )
}

fn f32_bytes(n: usize) -> Vec<u8> {
    (0..n).flat_map(|i| (i as f32 * 0.125).to_le_bytes()).collect()
}

const ZLIB: &str = r#" compressor="vtkZLibDataCompressor""#;

/// A compressed image of 3 × 3 × 3 points whose U is as declared by `table` (`None`: the true
/// table).
fn compressed_vti(table: Option<Vec<u32>>, data: Option<Vec<u8>>) -> String {
    let raw = f32_bytes(81);
    let z = data.unwrap_or_else(|| zlib(&raw, 6));
    let table = table.unwrap_or_else(|| vec![1, raw.len() as u32, raw.len() as u32, z.len() as u32]);
    vti("0 2 0 2 0 2", "0.5 0.5 0.5", &compressed("U", 3, &table, &z), ZLIB)
}

/// A `.pvtu` of the pieces `sources`.
fn pvtu(sources: &[&str]) -> String {
    let pieces: String = sources.iter().map(|s| format!("<Piece Source=\"{s}\"/>\n")).collect();
    format!(
        r#"{HEAD}
<VTKFile type="PUnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt32">
<PUnstructuredGrid GhostLevel="0">
<PPointData><PDataArray type="Float32" Name="U" NumberOfComponents="3"/></PPointData>
<PPoints><PDataArray type="Float64" Name="Points" NumberOfComponents="3"/></PPoints>
{pieces}</PUnstructuredGrid>
</VTKFile>
"#
    )
}

fn pvd(entries: &[(&str, &str)]) -> String {
    let sets: String = entries
        .iter()
        .map(|(t, f)| format!("<DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{f}\"/>\n"))
        .collect();
    format!(
        "{HEAD}\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n{sets}</Collection>\n</VTKFile>\n"
    )
}

// ----- Point 5: recursion ------------------------------------------------------------------

#[test]
fn a_pvtu_of_one_vtu_piece_is_read() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(fixture("hex_ascii.vtu"), dir.path().join("piece.vtu")).unwrap();
    std::fs::write(dir.path().join("all.pvtu"), pvtu(&["piece.vtu"])).unwrap();
    assert_eq!(read(&dir.path().join("all.pvtu")), None);
}

#[test]
fn a_pvtu_that_lists_itself_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("self.pvtu"), pvtu(&["self.pvtu"])).unwrap();
    let e = refused_file(&dir.path().join("self.pvtu"));
    says(&e, &["self.pvtu", "piece 0", "the pieces of a .pvtu are .vtu files"]);
    let e = refused(dir.path(), &field("self.pvtu"));
    says(&e, &["fluid.flow.file", "self.pvtu"]);
}

#[test]
fn two_pvtus_that_list_each_other_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.pvtu"), pvtu(&["b.pvtu"])).unwrap();
    std::fs::write(dir.path().join("b.pvtu"), pvtu(&["a.pvtu"])).unwrap();
    says(&refused_file(&dir.path().join("a.pvtu")), &["a.pvtu", "b.pvtu", "read without end"]);
    // Through a folder, a link or another name: still a piece that is not a .vtu.
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("sub/c.pvtu"), pvtu(&["../a.pvtu", "c.pvtu"])).unwrap();
    says(&refused_file(&dir.path().join("sub/c.pvtu")), &["c.pvtu", "a.pvtu"]);
    std::os::unix::fs::symlink(dir.path().join("d.pvtu"), dir.path().join("d.vtu")).unwrap();
    std::fs::write(dir.path().join("d.pvtu"), pvtu(&["d.vtu"])).unwrap();
    says(&refused_file(&dir.path().join("d.pvtu")), &["d.pvtu", "d.vtu", "PUnstructuredGrid"]);
}

// ----- Point 6: memory bombs ---------------------------------------------------------------

#[test]
fn a_498_byte_vti_declaring_two_billion_points_is_refused_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let text = vti("0 2000000000 0 2 0 2", "1 1 1", &ascii("U", "Float32", 3, 3), "");
    assert!(text.len() < 600);
    std::fs::write(dir.path().join("bomb.vti"), text).unwrap();
    let e = refused_file(&dir.path().join("bomb.vti"));
    says(&e, &["bomb.vti", "Extent \"0 2000000000 0 2 0 2\"", "1.800e10 points", "bytes hold"]);
}

#[test]
fn a_vts_whose_extent_product_wraps_is_refused_not_taken_for_zero_points() {
    let dir = tempfile::tempdir().unwrap();
    // 2²² nodes per axis: 2⁶⁶ points, which wraps to 0 in 64 bits.
    let whole = "0 4194303 0 4194303 0 4194303";
    let text = format!(
        r#"{HEAD}
<VTKFile type="StructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt32">
<StructuredGrid WholeExtent="{whole}"><Piece Extent="{whole}">
<PointData>{}</PointData>
<Points>{}</Points>
</Piece></StructuredGrid></VTKFile>"#,
        ascii("U", "Float32", 3, 0),
        ascii("Points", "Float32", 3, 0)
    );
    std::fs::write(dir.path().join("wrap.vts"), text).unwrap();
    says(
        &refused_file(&dir.path().join("wrap.vts")),
        &["wrap.vts", whole, "more points than can be counted"],
    );
}

#[test]
fn a_legacy_structured_points_of_two_billion_per_axis_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = "# vtk DataFile Version 3.0\nbomb\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2000000000 \
                2000000000 2000000000\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 1\nVECTORS U float\n0 0 0\n";
    std::fs::write(dir.path().join("bomb.vtk"), text).unwrap();
    says(
        &refused_file(&dir.path().join("bomb.vtk")),
        &["bomb.vtk", "DIMENSIONS 2000000000", "8e27 points", "bytes hold"],
    );
    // A product that wraps 64 bits is no smaller.
    let text = text.replace("2000000000 2000000000 2000000000", "4294967295 4294967295 4294967295");
    std::fs::write(dir.path().join("wrap.vtk"), text).unwrap();
    says(&refused_file(&dir.path().join("wrap.vtk")), &["wrap.vtk", "DIMENSIONS 4294967295"]);
}

#[test]
fn a_one_megabyte_zlib_block_declaring_a_gibibyte_is_refused_before_inflating() {
    let dir = tempfile::tempdir().unwrap();
    // 1 MiB of zlib data (stored, so that it is that long) declaring 1 GiB once inflated.
    let data = zlib(&vec![7u8; 1 << 20], 0);
    let table = vec![1, 1 << 30, 1 << 30, data.len() as u32];
    std::fs::write(dir.path().join("bomb.vti"), compressed_vti(Some(table), Some(data))).unwrap();
    says(
        &refused_file(&dir.path().join("bomb.vti")),
        &["bomb.vti", "array \"U\"", "1.074e9 bytes once inflated", "need 81, 324 bytes"],
    );
    // A block table that declares more than the cap, or more than zlib can inflate to.
    let table = vec![4, 1 << 30, 1 << 30, 100, 100, 100, 100];
    std::fs::write(dir.path().join("cap.vti"), compressed_vti(Some(table), Some(vec![0; 400]))).unwrap();
    says(&refused_file(&dir.path().join("cap.vti")), &["cap.vti", "beyond the 1024 MiB the reader takes"]);
    let table = vec![1, 324, 324, 0];
    std::fs::write(dir.path().join("ratio.vti"), compressed_vti(Some(table), Some(vec![]))).unwrap();
    says(&refused_file(&dir.path().join("ratio.vti")), &["ratio.vti", "1032-fold"]);
}

#[test]
fn a_true_compressed_image_is_read() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("z.vti"), compressed_vti(None, None)).unwrap();
    assert_eq!(read(&dir.path().join("z.vti")), None);
}

// ----- Point 7: device files ---------------------------------------------------------------

/// Every kind of path that is not a regular file: devices, a folder, a fifo.
fn not_regular(dir: &Path) -> Vec<(&'static str, PathBuf)> {
    let mut out = Vec::new();
    for device in ["/dev/zero", "/dev/urandom", "/dev/null"] {
        if Path::new(device).exists() {
            out.push((device, PathBuf::from(device)));
        }
    }
    let folder = dir.join("a_folder");
    std::fs::create_dir_all(&folder).unwrap();
    out.push(("a folder", folder));
    let fifo = dir.join("a_fifo");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path; mkfifo only creates the node.
    if unsafe { libc::mkfifo(c.as_ptr(), 0o600) } == 0 {
        out.push(("a fifo", fifo));
    }
    out
}

#[test]
fn dev_zero_and_urandom_as_a_field_file_a_pvd_data_set_or_a_pvtu_piece_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for device in ["/dev/zero", "/dev/urandom"] {
        let stem = device.trim_start_matches("/dev/");
        let file = format!("{stem}.vti");
        std::os::unix::fs::symlink(device, dir.path().join(&file)).unwrap();
        says(&refused(dir.path(), &field(&file)), &[&file, "not a regular file"]);
        std::fs::write(dir.path().join(format!("{stem}.pvd")), pvd(&[("0", &file)])).unwrap();
        says(&refused(dir.path(), &field(&format!("{stem}.pvd"))), &[&file, "not a regular file"]);
        let piece = format!("{stem}.vtu");
        std::os::unix::fs::symlink(device, dir.path().join(&piece)).unwrap();
        std::fs::write(dir.path().join(format!("{stem}.pvtu")), pvtu(&[&piece])).unwrap();
        says(
            &refused(dir.path(), &field(&format!("{stem}.pvtu"))),
            &[&piece, "piece 0", "not a regular file"],
        );
    }
}

/// Class: every path that is not a regular file, in every role a file has (a field file of
/// each format, a `.pvd`, a data set of a `.pvd`, a `.pvtu` piece, a scene file, a mesh file),
/// is refused naming it, before a byte is read.
#[test]
fn no_role_reads_a_device_a_folder_or_a_fifo() {
    let dir = tempfile::tempdir().unwrap();
    for (what, target) in not_regular(dir.path()) {
        for ext in ["vti", "vtr", "vts", "vtu", "pvtu", "vtk", "pvd"] {
            let file = format!("x.{ext}");
            let link = dir.path().join(&file);
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink(&target, &link).unwrap();
            says(&refused(dir.path(), &field(&file)), &[&file, "not a regular file"]);
            if ext != "pvd" {
                std::fs::write(dir.path().join("s.pvd"), pvd(&[("0", &file)])).unwrap();
                says(&refused(dir.path(), &field("s.pvd")), &[&file, "not a regular file"]);
            }
        }
        std::fs::write(dir.path().join("p.pvtu"), pvtu(&["x.vtu"])).unwrap();
        says(&refused(dir.path(), &field("p.pvtu")), &["x.vtu", "not a regular file"]);
        let e = Scene::load(&target).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{what} as a scene: {e}");
        let walls = "\n[[walls]]\nname = \"plate\"\ntype = \"mesh\"\nfile = \"x.stl\"\n";
        let _ = std::fs::remove_file(dir.path().join("x.stl"));
        std::os::unix::fs::symlink(&target, dir.path().join("x.stl")).unwrap();
        let text = scene(r#"{ type = "uniform", velocity = [0.0, 0.0, 0.0] }"#) + walls;
        match Scene::from_str(&text, &dir.path().join("scene.toml")) {
            Ok(_) => panic!("{what} accepted as a mesh"),
            Err(e) => says(&e.to_string(), &["x.stl", "not a regular file"]),
        }
    }
}

// ----- Point 8: .pvd read as XML -----------------------------------------------------------

#[test]
fn a_pvd_with_non_ascii_characters_after_file_or_timestep_is_read_not_panicked_on() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("données é.vti"), good_vti()).unwrap();
    std::fs::write(dir.path().join("a.pvd"), pvd(&[("0", "données é.vti")])).unwrap();
    Scene::from_str(&scene(&field("a.pvd")), &dir.path().join("scene.toml")).unwrap();
    // A character of several bytes right after the quote.
    std::fs::write(dir.path().join("b.pvd"), pvd(&[("é1", "données é.vti")])).unwrap();
    says(&refused(dir.path(), &field("b.pvd")), &["b.pvd", "timestep \"é1\"", "not a finite number"]);
    std::fs::write(dir.path().join("c.pvd"), pvd(&[("0", "ü.vti")])).unwrap();
    says(&refused(dir.path(), &field("c.pvd")), &["ü.vti", "cannot read the field file"]);
    // Unquoted, the attribute is not XML: an error, not a slice inside a character.
    let text = pvd(&[("0", "a.vti")]).replace("file=\"a.vti\"", "file=é");
    std::fs::write(dir.path().join("d.pvd"), text).unwrap();
    let e = refused(dir.path(), &field("d.pvd"));
    assert!(
        e.contains("d.pvd") && (e.contains("malformed attribute") || e.contains("not well-formed")),
        "{e}"
    );
    // Escapes are read as XML reads them.
    std::fs::write(dir.path().join("a&b.vti"), good_vti()).unwrap();
    std::fs::write(dir.path().join("e.pvd"), pvd(&[("0", "a&amp;b.vti")])).unwrap();
    Scene::from_str(&scene(&field("e.pvd")), &dir.path().join("scene.toml")).unwrap();
}

#[test]
fn a_commented_out_data_set_is_not_a_snapshot() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("kept.vti"), good_vti()).unwrap();
    let text = pvd(&[("0", "kept.vti")])
        .replace("</Collection>", "<!-- <DataSet timestep=\"1\" file=\"removed.vti\"/> -->\n</Collection>");
    std::fs::write(dir.path().join("s.pvd"), text).unwrap();
    let s = Scene::from_str(&scene(&field("s.pvd")), &dir.path().join("scene.toml")).unwrap();
    let files = &s.setup.fluid.flow.field().unwrap().info.files;
    assert_eq!(files.len(), 1, "the commented-out data set was read: {files:?}");
    // Commented out alone: the collection names no data set.
    let text = pvd(&[])
        .replace("</Collection>", "<!-- <DataSet timestep=\"0\" file=\"kept.vti\"/> -->\n</Collection>");
    std::fs::write(dir.path().join("t.pvd"), text).unwrap();
    says(&refused(dir.path(), &field("t.pvd")), &["t.pvd", "names no data set"]);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Class: a `.pvd` with any character (of 1 to 4 bytes) put anywhere, or cut anywhere, is
    /// read or refused naming it, never a panic.
    #[test]
    fn a_pvd_with_any_character_anywhere_is_read_or_refused(at in 0usize..400, c in any::<char>(), cut in any::<bool>()) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.vti"), good_vti()).unwrap();
        let mut text = pvd(&[("0", "a.vti"), ("1", "a.vti")]);
        let mut at = at.min(text.len());
        while !text.is_char_boundary(at) { at -= 1; }
        if cut { text.truncate(at) } else { text.insert(at, c) }
        std::fs::write(dir.path().join("s.pvd"), &text).unwrap();
        if let Err(e) = Scene::from_str(&scene(&field("s.pvd")), &dir.path().join("scene.toml")) {
            let e = e.to_string();
            prop_assert!(e.contains("s.pvd") || e.contains("a.vti"), "{}", e);
        }
    }
}

// ----- Point 9: messages -------------------------------------------------------------------

/// The wrong arrays: each is named, with what is wrong, never reported missing.
#[test]
fn an_array_of_the_wrong_length_components_or_type_is_named_not_reported_missing() {
    let dir = tempfile::tempdir().unwrap();
    let f = f32_bytes(81);
    let cases: Vec<(&str, String, &[&str])> = vec![
        ("short", ascii("U", "Float64", 3, 80), &["holds 80 values", "27 points × 3 components need 81"]),
        ("long", ascii("U", "Float64", 3, 82), &["holds 82 values"]),
        ("two_components", ascii("U", "Float64", 2, 81), &["holds 81 values", "× 2 components need 54"]),
        ("four_components", ascii("U", "Float64", 4, 81), &["× 4 components need 108"]),
        ("zero_components", ascii("U", "Float64", 0, 81), &["NumberOfComponents=\"0\""]),
        ("integers_with_fractions", ascii("U", "Int32", 3, 81), &["is not a number of its type Int32"]),
        ("unknown_type", ascii("U", "Float3", 3, 81), &["type \"Float3\", not one of VTK's"]),
        ("words", ascii("U", "Float64", 3, 81).replace(">0 ", ">zero "), &["value 0 \"zero\""]),
        (
            "binary_short",
            binary("U", "Float32", 3, 320, &f[..320]),
            &["holds 320 bytes", "need 81, 324 bytes"],
        ),
        (
            "binary_as_float64",
            binary("U", "Float64", 3, 324, &f),
            &["holds 324 bytes of Float64", "648 bytes"],
        ),
        ("binary_not_base64", ascii("U", "Float32", 3, 81).replace("ascii", "binary"), &["not base64"]),
        ("bad_format", ascii("U", "Float32", 3, 81).replace("ascii", "hex"), &["format \"hex\""]),
        (
            "appended_without_data",
            ascii("U", "Float32", 3, 81).replace("ascii", "appended"),
            &["no <AppendedData>"],
        ),
    ];
    for (name, array, parts) in &cases {
        let file = format!("{name}.vti");
        std::fs::write(dir.path().join(&file), vti("0 2 0 2 0 2", "0.5 0.5 0.5", array, "")).unwrap();
        let e = refused_file(&dir.path().join(&file));
        assert!(!e.contains("no velocity array"), "{name}: {e}");
        says(&e, &[&file, "array \"U\" (point data of piece 0)"]);
        says(&e, parts);
    }
    // Cell data of the wrong length, and an array in an unstructured grid's cells.
    let text = std::fs::read_to_string(fixture("hex_ascii.vtu")).unwrap();
    let short = text.replacen("1.25 0.75 -0.125 ", "", 1);
    std::fs::write(dir.path().join("cells.vtu"), short).unwrap();
    says(
        &refused_file(&dir.path().join("cells.vtu")),
        &[
            "cells.vtu",
            "array \"U\" (cell data of piece 0) holds 21 values",
            "8 cells × 3 components need 24",
        ],
    );
    let lying = text.replace("NumberOfCells=\"8\"", "NumberOfCells=\"9\"");
    std::fs::write(dir.path().join("nine.vtu"), lying).unwrap();
    says(&refused_file(&dir.path().join("nine.vtu")), &["nine.vtu", "9 cells"]);
}

#[test]
fn a_cell_1e150_m_tall_is_too_large_not_degenerate() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixture("hex_ascii.vtu")).unwrap();
    // The points' z of 1 becomes 1e150.
    let start = text.find("Name=\"Points\"").unwrap();
    let end = start + text[start..].find("</DataArray>").unwrap();
    let open = start + text[start..].find('>').unwrap() + 1;
    let values: Vec<String> = text[open..end]
        .split_whitespace()
        .enumerate()
        .map(|(i, v)| if i % 3 == 2 && v == "1.0" { "1e150".to_string() } else { v.to_string() })
        .collect();
    let tall = format!("{}{}{}", &text[..open], values.join(" "), &text[end..]);
    std::fs::write(dir.path().join("tall.vtu"), tall).unwrap();
    let e = refused_file(&dir.path().join("tall.vtu"));
    says(&e, &["tall.vtu", "z coordinates span 1e150 m", "volume would overflow"]);
    assert!(!e.contains("degenerate"), "{e}");
}

#[test]
fn a_spacing_of_1e_300_is_shown_as_1e_300_not_0() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tiny.vti"),
        vti("0 2 0 2 0 2", "1e-300 0.5 0.5", &ascii("U", "Float64", 3, 81), ""),
    )
    .unwrap();
    says(
        &refused_file(&dir.path().join("tiny.vti")),
        &["tiny.vti", "Spacing \"1e-300 0.5 0.5\"", "1e-300 m along x"],
    );
    let legacy = "# vtk DataFile Version 3.0\ntiny\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nORIGIN 0 0 0\n\
                  SPACING 1 1e300 1\nPOINT_DATA 8\nVECTORS U float\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n";
    std::fs::write(dir.path().join("huge.vtk"), legacy).unwrap();
    says(
        &refused_file(&dir.path().join("huge.vtk")),
        &["huge.vtk", "SPACING \"1 1e300 1\"", "1e300 m along y"],
    );
    let legacy = legacy.replace("SPACING 1 1e300 1", "SPACING 1 -2 1");
    std::fs::write(dir.path().join("negative.vtk"), legacy).unwrap();
    says(&refused_file(&dir.path().join("negative.vtk")), &["negative.vtk", "-2 m along y must be > 0"]);
}

/// vtkio's panics never reach the terminal: the command line, given each bad file of the
/// corpus, prints a clean error naming the file and no panic or backtrace.
#[test]
fn no_bad_field_prints_a_panic_or_a_backtrace() {
    let dir = tempfile::tempdir().unwrap();
    for path in corpus(dir.path()).into_iter().step_by(9) {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let scene_path = dir.path().join("scene.toml");
        std::fs::write(&scene_path, scene(&field(&name))).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_wetbounce"))
            .args(["check", scene_path.to_str().unwrap()])
            .env("RUST_BACKTRACE", "1")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked") && !stderr.contains("backtrace"), "{name}: {stderr}");
        if !out.status.success() {
            assert!(stderr.contains(&name), "{name}: {stderr}");
        }
    }
}

// ----- The class: a corpus of bad files ----------------------------------------------------

/// Bad files of every kind, written into `dir`: the committed fixtures cut at many offsets,
/// with bytes flipped, and generated files whose extents, counts and block tables lie.
fn corpus(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut put = |name: String, bytes: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        out.push(p);
    };
    let mut sources: Vec<(String, Vec<u8>)> = [
        "hex_ascii.vtu",
        "hex_appended_raw.vtu",
        "hex_appended_zlib.vtu",
        "hex_base64_uint64.vtu",
        "hex_legacy_binary.vtk",
    ]
    .iter()
    .map(|f| (f.to_string(), std::fs::read(fixture(f)).unwrap()))
    .collect();
    sources.push(("good.vti".into(), good_vti().into_bytes()));
    sources.push(("zlib.vti".into(), compressed_vti(None, None).into_bytes()));
    for (name, bytes) in &sources {
        let (stem, ext) = name.rsplit_once('.').unwrap();
        let n = bytes.len();
        // Truncations: every 1/37 of the file and around the data's start.
        for k in 1..37 {
            let at = n * k / 37;
            put(format!("{stem}_cut{at}.{ext}"), &bytes[..at]);
        }
        // Flipped bytes: digits, quotes, base64 and binary alike.
        for k in 1..13 {
            let at = n * k / 13;
            let mut b = bytes.clone();
            b[at] ^= 0x5a;
            put(format!("{stem}_flip{at}.{ext}"), &b);
        }
    }
    // Lying extents and counts.
    for whole in [
        "0 2 0 2 0 2000000",
        "0 -2 0 2 0 2",
        "0 2147483647 0 2 0 2",
        "-2147483648 2147483647 0 0 0 0",
        "0 2 0 2",
        "a b c d e f",
        "0 2 0 2 0 2 0",
    ] {
        let tag = whole.len() + whole.bytes().map(usize::from).sum::<usize>();
        put(
            format!("extent{tag}.vti"),
            vti(whole, "0.5 0.5 0.5", &ascii("U", "Float64", 3, 81), "").as_bytes(),
        );
    }
    let text = std::fs::read_to_string(fixture("hex_ascii.vtu")).unwrap();
    for (k, lie) in [
        "NumberOfPoints=\"99999999999\"",
        "NumberOfPoints=\"-1\"",
        "NumberOfCells=\"18446744073709551615\"",
        "NumberOfPoints=\"26\"",
    ]
    .iter()
    .enumerate()
    {
        let key = lie.split('=').next().unwrap();
        let truth = if key == "NumberOfPoints" { "NumberOfPoints=\"27\"" } else { "NumberOfCells=\"8\"" };
        put(format!("count{k}.vtu"), text.replace(truth, lie).as_bytes());
    }
    // Connectivity whose last offset lies.
    put("offsets.vtu".into(), text.replace(" 64</DataArray>", " 6400000000</DataArray>").as_bytes());
    // Lying block tables.
    let raw = f32_bytes(81);
    let z = zlib(&raw, 6);
    let nc = z.len() as u32;
    for (k, table) in [
        vec![0],
        vec![0, 324, 324],
        vec![1, 324, 324, nc + 1000],
        vec![2, 324, 0, nc, nc],
        vec![u32::MAX, 324, 324, nc],
        vec![1, u32::MAX, u32::MAX, nc],
        vec![3, 108, 108, nc, 0, 0],
        vec![1, 0, 0, nc],
        vec![1, 324, 324],
    ]
    .into_iter()
    .enumerate()
    {
        put(format!("table{k}.vti"), compressed_vti(Some(table), Some(z.clone())).as_bytes());
    }
    // Raw appended data whose offsets and sizes lie.
    let rawfile = std::fs::read(fixture("hex_appended_raw.vtu")).unwrap();
    for (k, (from, to)) in [
        ("offset=\"0\"", "offset=\"99999999\""),
        ("offset=\"0\"", "offset=\"18446744073709551615\""),
        ("header_type=\"UInt32\"", "header_type=\"UInt64\""),
        ("header_type=\"UInt32\"", "header_type=\"Int8\""),
    ]
    .iter()
    .enumerate()
    {
        if let Some(i) = find(&rawfile, from.as_bytes()) {
            let mut b = rawfile[..i].to_vec();
            b.extend_from_slice(to.as_bytes());
            b.extend_from_slice(&rawfile[i + from.len()..]);
            put(format!("rawlie{k}.vtu"), &b);
        }
    }
    // Lying size words inside raw appended data: every size word set to 2³² − 1.
    if let Some(u) = find(&rawfile, b"_") {
        let mut b = rawfile.clone();
        for w in b[u + 1..u + 5].iter_mut() {
            *w = 0xff;
        }
        put("rawsize.vtu".into(), &b);
    }
    // Legacy headers that lie.
    let legacy = std::fs::read(fixture("hex_legacy_binary.vtk")).unwrap();
    let ltext = String::from_utf8_lossy(&legacy).to_string();
    for (k, lie) in [
        "POINTS 4000000000 float",
        "CELLS 4000000000 4000000000",
        "POINT_DATA 4000000000",
        "CELL_TYPES 4000000000",
    ]
    .iter()
    .enumerate()
    {
        let key = lie.split(' ').next().unwrap();
        if let Some(line) = ltext.lines().find(|l| l.starts_with(key))
            && let Some(i) = find(&legacy, line.as_bytes())
        {
            let mut b = legacy[..i].to_vec();
            b.extend_from_slice(lie.as_bytes());
            b.extend_from_slice(&legacy[i + line.len()..]);
            put(format!("legacy{k}.vtk"), &b);
        }
    }
    // Files that are not what their name says.
    put("empty.vti".into(), b"");
    put("text.vtu".into(), b"not xml at all");
    put("image_as.vtu".into(), good_vti().as_bytes());
    put("zeros.vtk".into(), &[0u8; 4096]);
    put("nested.vti".into(), good_vti().replace("<PointData>", "<PointData><PointData>").as_bytes());
    out
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Class: every file of the corpus is read or refused naming the file, by the reader's own
/// checks; and the cut files, all of which lack something, are all refused.
#[test]
fn every_bad_file_of_the_corpus_is_refused_naming_it_never_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let files = corpus(dir.path());
    assert!(files.len() > 300, "{}", files.len());
    let mut accepted = Vec::new();
    for path in &files {
        if read(path).is_none() {
            accepted.push(path.file_name().unwrap().to_string_lossy().to_string());
        }
    }
    // A flipped byte may land in a value (0.5 becoming 0.o is refused, but a digit may stay
    // a digit); a cut never leaves a whole file.
    assert!(accepted.iter().all(|n| !n.contains("_cut") && !n.starts_with("table")), "{accepted:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Class: an image whose extent, counts and U array are random lies is read only when they
    /// agree, and otherwise refused naming the file.
    #[test]
    fn random_extents_and_arrays_are_read_only_when_they_agree(
        x in -3i64..3, nx in prop_oneof![0i64..5, Just(2_000_000_000i64), Just(2_147_483_647i64)],
        comps in 0u32..5, n in 0usize..120, ty in prop::sample::select(vec!["Float32", "Float64", "Int32", "UInt8", "Float16"]),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let whole = format!("{x} {} 0 2 0 2", x.saturating_add(nx));
        std::fs::write(dir.path().join("r.vti"), vti(&whole, "0.5 0.5 0.5", &ascii("U", ty, comps, n), "")).unwrap();
        let agree = nx >= 1 && comps == 3 && n as i64 == (nx + 1) * 9 * 3 && ty != "Float16";
        let result = read(&dir.path().join("r.vti"));
        prop_assert!(agree || result.is_some(), "accepted {} {} {} {}", whole, comps, n, ty);
    }

    /// Class: a compressed array whose block table is random is read only when it is true.
    #[test]
    fn random_block_tables_are_refused_naming_the_file(
        nb in prop_oneof![0u32..4, Just(u32::MAX)], nu in prop_oneof![0u32..400, Just(u32::MAX), Just(1 << 30)],
        np in 0u32..400, nc in prop_oneof![0u32..400, Just(u32::MAX)], extra in 0usize..3,
    ) {
        let dir = tempfile::tempdir().unwrap();
        let z = zlib(&f32_bytes(81), 6);
        let mut table = vec![nb, nu, np];
        table.extend(std::iter::repeat_n(nc, (nb.min(3) as usize + extra).min(6)));
        std::fs::write(dir.path().join("t.vti"), compressed_vti(Some(table), Some(z))).unwrap();
        let _ = read(&dir.path().join("t.vti"));
    }

    /// Class: a file cut at any byte is refused naming it.
    #[test]
    fn a_file_cut_anywhere_is_refused(which in 0usize..6, at in any::<prop::sample::Index>()) {
        let names = ["hex_ascii.vtu", "hex_appended_raw.vtu", "hex_appended_zlib.vtu", "hex_base64_uint64.vtu", "hex_legacy_binary.vtk", "zlib.vti"];
        let bytes = if which == 5 { compressed_vti(None, None).into_bytes() } else { std::fs::read(fixture(names[which])).unwrap() };
        // The last bytes are a closing tag's newline: cut before the root closes.
        let end = bytes.len() - 12;
        let cut = at.index(end);
        // The legacy file holds the velocity twice, as cell data and then as point data: cut
        // just before `POINT_DATA`, or just after its header line (`POINT_DATA 27`, with or
        // without its newline, no arrays after it), it is a whole file with cell data only,
        // which is read (as it should be). Every other cut leaves a part of a section (every
        // cut of this file tried: only these four are read).
        if let Some(point_data) = bytes.windows(10).position(|w| w == b"POINT_DATA") {
            let line_end = point_data + bytes[point_data..].iter().position(|&b| b == b'\n').unwrap_or(0);
            let whole = (point_data - 1..=point_data).contains(&cut) || (line_end..=line_end + 1).contains(&cut);
            prop_assume!(which != 4 || !whole);
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(names[which]);
        std::fs::write(&path, &bytes[..cut]).unwrap();
        prop_assert!(read(&path).is_some(), "{} cut at {} accepted", names[which], cut);
    }
}

/// The bounds `wetbounce check` prints are written short: a field 1e100 m wide is not shown
/// with a hundred digits.
#[test]
fn bounds_are_printed_short_not_digit_by_digit() {
    let dir = tempfile::tempdir().unwrap();
    let coords = |values: &str| format!(r#"<DataArray type="Float64" format="ascii">{values}</DataArray>"#);
    // At rest: a gradient across the 1e-7 m would limit dt.
    let velocity = format!(
        r#"<DataArray type="Float64" Name="U" NumberOfComponents="3" format="ascii">{}</DataArray>"#,
        ["0"; 24].join(" ")
    );
    let text = format!(
        r#"{HEAD}
<VTKFile type="RectilinearGrid" version="1.0" byte_order="LittleEndian">
<RectilinearGrid WholeExtent="0 1 0 1 0 1"><Piece Extent="0 1 0 1 0 1">
<PointData>{}</PointData>
<Coordinates>{}{}{}</Coordinates>
</Piece></RectilinearGrid></VTKFile>"#,
        velocity,
        coords("-1e100 1e100"),
        coords("0 1"),
        coords("0 1e-7")
    );
    std::fs::write(dir.path().join("wide.vtr"), text).unwrap();
    let scene_path = dir.path().join("scene.toml");
    std::fs::write(&scene_path, scene(&field("wide.vtr"))).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .args(["check", scene_path.to_str().unwrap()])
        .output()
        .unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let bounds = text.lines().find(|l| l.contains("bounds:")).unwrap_or_else(|| panic!("no bounds: {text}"));
    says(bounds, &["[-1e100, 0, 0]", "[1e100, 1, 1e-7]"]);
    assert!(!bounds.contains("0000000000"), "{bounds}");
}
