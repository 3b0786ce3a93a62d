//! An XML VTK file vetted before `vtkio` reads it (issue 25): every size the file declares is
//! compared, in checked arithmetic, with what the file holds, so that `vtkio` neither
//! allocates what a few bytes claim (a 498-byte `.vti` of 2·10⁹ points, a block table that
//! inflates to a gigabyte), nor slices past the data (a panic), nor silently drops an array
//! whose length, component count or type is wrong (which left the engine saying "no velocity
//! array"). Each refusal names the element, the array and the bad value; the caller adds the
//! file.
//!
//! The rules mirror what `vtkio` 0.7.0-rc2 computes: the points of an extent `(x1 − x0 + 1)·…`,
//! its cells `(nx − 1)(ny − 1)(nz − 1)`, an array's values as tuples × components, the
//! connectivity's length as the last offset, and compressed data as a block table
//! `[nb][nu][np][nc_1 … nc_nb]` base64-encoded apart from the blocks.

use super::DataAt;
use base64::Engine;
use quick_xml::events::{BytesStart, Event};
use std::borrow::Cow;

/// The most a file's compressed arrays may inflate to together (bytes): 1 GiB, some 45
/// million points of a 32-bit velocity with their coordinates. A hard cap, because zlib
/// inflates up to 1032-fold and the file's own size does not bound it.
pub const INFLATE_CAP: u64 = 1 << 30;

/// zlib's largest inflation: a deflate stream of `n` bytes holds at most `1032 n` bytes.
const DEFLATE_RATIO: u64 = 1032;

/// VTK's value types and their sizes (bytes).
const TYPES: [(&str, u64); 10] = [
    ("Int8", 1),
    ("UInt8", 1),
    ("Int16", 2),
    ("UInt16", 2),
    ("Int32", 4),
    ("UInt32", 4),
    ("Int64", 8),
    ("UInt64", 8),
    ("Float32", 4),
    ("Float64", 8),
];

/// The XML data set type a file of each extension holds.
const KINDS: [(&str, &str); 5] = [
    ("vti", "ImageData"),
    ("vtr", "RectilinearGrid"),
    ("vts", "StructuredGrid"),
    ("vtu", "UnstructuredGrid"),
    ("pvtu", "PUnstructuredGrid"),
];

/// An element's attributes: (name, unescaped value).
type Attrs = Vec<(String, String)>;

/// Where a data array sits.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Section {
    Point,
    Cell,
    Points,
    Coordinates(usize),
    Cells,
    /// Field data and anything else: checked for itself, not against the grid.
    Other,
}

#[derive(Debug)]
struct Array<'a> {
    piece: usize,
    section: Section,
    attrs: Vec<(String, String)>,
    text: Vec<Cow<'a, [u8]>>,
}

impl Array<'_> {
    fn attr(&self, key: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }

    fn name(&self) -> String {
        self.attr("Name").unwrap_or("(unnamed)").to_string()
    }

    /// `array "U" (point data of piece 0)`.
    fn label(&self) -> String {
        let place = match self.section {
            Section::Point => "point data".to_string(),
            Section::Cell => "cell data".to_string(),
            Section::Points => "points".to_string(),
            Section::Coordinates(a) => format!("{} coordinates", ["x", "y", "z"][a.min(2)]),
            Section::Cells => "cells".to_string(),
            Section::Other => "field data".to_string(),
        };
        format!("array \"{}\" ({place} of piece {})", self.name(), self.piece)
    }

    /// The text content, whitespace-trimmed as `vtkio` trims it.
    fn content(&self) -> Cow<'_, [u8]> {
        let joined: Cow<[u8]> = match self.text.as_slice() {
            [] => Cow::Borrowed(&[]),
            [one] => Cow::Borrowed(one.as_ref()),
            many => Cow::Owned(many.iter().flat_map(|t| t.iter().copied()).collect()),
        };
        match joined {
            Cow::Borrowed(b) => Cow::Borrowed(b.trim_ascii()),
            Cow::Owned(b) => Cow::Owned(b.trim_ascii().to_vec()),
        }
    }
}

#[derive(Debug, Default)]
struct Piece {
    attrs: Vec<(String, String)>,
}

impl Piece {
    fn attr(&self, key: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }
}

/// The file's encoding: the size of a header word, compression, byte order.
struct Encoding {
    word: u64,
    compressed: bool,
    little: bool,
}

/// Vets the XML VTK text `xml` of a file named `.{ext}`, `file_len` bytes on disk; the point
/// and cell data arrays it holds (`vtkio` drops an array it cannot decode: the reader then
/// names it rather than report it missing).
pub fn vet(xml: &[u8], ext: &str, file_len: u64) -> Result<Vec<(DataAt, String)>, String> {
    let mut reader = quick_xml::Reader::from_reader(xml);
    let mut root: Option<Vec<(String, String)>> = None;
    let mut data_set: Option<(String, Vec<(String, String)>)> = None;
    let mut pieces: Vec<Piece> = Vec::new();
    let mut arrays: Vec<Array> = Vec::new();
    let mut appended: Option<(Attrs, Vec<Cow<[u8]>>)> = None;
    // The open elements' names: text belongs to an array (or to the appended data) only
    // directly inside it, not inside an element it holds (ParaView's <InformationKey>).
    let mut stack: Vec<String> = Vec::new();
    let mut coordinate = 0usize;
    loop {
        let at = reader.buffer_position();
        let event = reader.read_event().map_err(|e| format!("is not well-formed XML near byte {at}: {e}"))?;
        let (start, empty) = match &event {
            Event::Start(e) => (Some(e), false),
            Event::Empty(e) => (Some(e), true),
            _ => (None, false),
        };
        if let Some(e) = start {
            let name = String::from_utf8_lossy(e.local_name().as_ref()).into_owned();
            let attrs = attributes(e)?;
            let parent = stack.last().map(String::as_str);
            match name.as_str() {
                "VTKFile" if root.is_none() => root = Some(attrs),
                "Piece" => {
                    pieces.push(Piece { attrs });
                    coordinate = 0;
                }
                "DataArray" => {
                    let section = match parent {
                        Some("PointData") => Section::Point,
                        Some("CellData") => Section::Cell,
                        Some("Points") => Section::Points,
                        Some("Coordinates") => {
                            coordinate += 1;
                            Section::Coordinates(coordinate - 1)
                        }
                        Some("Cells") => Section::Cells,
                        _ => Section::Other,
                    };
                    let piece = pieces.len().saturating_sub(1);
                    arrays.push(Array { piece, section, attrs, text: Vec::new() });
                }
                "AppendedData" => {
                    appended = Some((attrs, Vec::new()));
                }
                _ if stack.len() == 1 && data_set.is_none() => data_set = Some((name.clone(), attrs)),
                _ => {}
            }
            if !empty {
                stack.push(name);
            }
            continue;
        }
        match event {
            Event::End(_) => {
                stack.pop();
            }
            Event::Text(t) => {
                match (stack.last().map(String::as_str), arrays.last_mut(), appended.as_mut()) {
                    (Some("DataArray"), Some(a), _) => a.text.push(t.into_inner()),
                    (Some("AppendedData"), _, Some((_, text))) => text.push(t.into_inner()),
                    _ => {}
                }
            }
            Event::CData(t) => {
                if stack.last().map(String::as_str) == Some("DataArray")
                    && let Some(a) = arrays.last_mut()
                {
                    a.text.push(t.into_inner());
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    let root = root.ok_or("has no <VTKFile> element")?;
    let get =
        |attrs: &[(String, String)], key: &str| attrs.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
    let want = KINDS.iter().find(|(e, _)| *e == ext).map_or("", |(_, k)| *k);
    let kind = get(&root, "type").unwrap_or_default();
    if kind != want {
        return Err(format!("declares type=\"{kind}\"; a .{ext} file holds {want}"));
    }
    let (set_name, set_attrs) = data_set.ok_or_else(|| format!("has no <{want}> element"))?;
    if set_name != want {
        return Err(format!("holds a <{set_name}> element where its type says <{want}>"));
    }
    // A parallel file's pieces are read (and vetted) as files of their own.
    if ext == "pvtu" {
        return Ok(Vec::new());
    }
    let encoding = Encoding {
        word: match get(&root, "header_type").as_deref() {
            None | Some("UInt32") => 4,
            Some("UInt64") => 8,
            Some(other) => return Err(format!("has header_type=\"{other}\": expected UInt32 or UInt64")),
        },
        compressed: match get(&root, "compressor").as_deref() {
            None | Some("") => false,
            Some("vtkZLibDataCompressor") => true,
            Some(other) => {
                return Err(format!(
                    "is compressed with {other}; the reader takes zlib (vtkZLibDataCompressor) or none"
                ));
            }
        },
        little: get(&root, "byte_order").as_deref() != Some("BigEndian"),
    };
    // A value takes a byte at least, before compression; compressed data at most INFLATE_CAP.
    let budget = file_len.saturating_add(if encoding.compressed { INFLATE_CAP } else { 0 });
    let holds = || {
        if encoding.compressed {
            format!(
                "the file's {file_len} bytes and the {} its compressed arrays may inflate to hold",
                crate::files::size(INFLATE_CAP)
            )
        } else {
            format!("the file's {file_len} bytes hold (a value takes a byte at least)")
        }
    };
    let structured = ext != "vtu";
    if structured && let Some(spacing) = get(&set_attrs, "Spacing") {
        let whole = get(&set_attrs, "WholeExtent").and_then(|t| extent(&t).ok()).map(|e| e.2);
        vet_spacing("Spacing", &spacing, whole)?;
    }
    // Points, cells and (structured) nodes per axis of each piece.
    let mut sizes: Vec<(u64, u64, [u64; 3])> = Vec::new();
    for (i, p) in pieces.iter().enumerate() {
        if structured {
            let (key, text) = match p.attr("Extent") {
                Some(t) => (format!("piece {i}'s Extent"), t.to_string()),
                None => (
                    format!("{want}'s WholeExtent"),
                    get(&set_attrs, "WholeExtent").ok_or_else(|| format!("its piece {i} has no Extent"))?,
                ),
            };
            let (points, cells, dims) = extent(&text).map_err(|m| format!("{key} \"{text}\" {m}"))?;
            if points > budget {
                return Err(format!(
                    "{key} \"{text}\" declares {} points, more than {}",
                    big(points),
                    holds()
                ));
            }
            sizes.push((points, cells, dims));
        } else {
            let count = |key: &str| -> Result<u64, String> {
                let text = p.attr(key).ok_or_else(|| format!("its piece {i} has no {key}"))?;
                let n: u64 = text
                    .trim()
                    .parse()
                    .map_err(|_| format!("its piece {i} has {key}=\"{text}\", not a count"))?;
                if n > budget {
                    return Err(format!("its piece {i} declares {key}=\"{text}\", more than {}", holds()));
                }
                Ok(n)
            };
            sizes.push((count("NumberOfPoints")?, count("NumberOfCells")?, [0; 3]));
        }
    }
    // `vtkio` reads the points and (unstructured) the cells without checking they are there.
    for (i, _) in pieces.iter().enumerate() {
        let has = |s: Section| arrays.iter().any(|a| a.piece == i && a.section == s);
        if matches!(ext, "vts" | "vtu") && !has(Section::Points) {
            return Err(format!("its piece {i} has no <Points> array"));
        }
        if ext == "vtr" && !(0..3).all(|a| has(Section::Coordinates(a))) {
            return Err(format!("its piece {i} lacks <Coordinates> arrays: it needs three (x, y, z)"));
        }
        if ext == "vtu" {
            for name in ["connectivity", "offsets", "types"] {
                if !arrays
                    .iter()
                    .any(|a| a.piece == i && a.section == Section::Cells && a.attr("Name") == Some(name))
                {
                    return Err(format!("its piece {i} has no \"{name}\" array in <Cells>"));
                }
            }
        }
    }
    let appended_text: Option<Vec<u8>> = appended.as_ref().map(|(_, text)| {
        let joined: Vec<u8> = text.iter().flat_map(|t| t.iter().copied()).collect();
        let t = joined.trim_ascii();
        t.strip_prefix(b"_").unwrap_or(t).to_vec()
    });
    if let Some((attrs, _)) = &appended
        && get(attrs, "encoding").as_deref().is_some_and(|e| e != "base64")
    {
        return Err("its <AppendedData> is neither raw nor base64".into());
    }
    let mut inflated = 0u64;
    for a in &arrays {
        let grid = sizes.get(a.piece).copied();
        let (points, cells, dims) = match (a.section, grid) {
            (Section::Other, _) => (0, 0, [0; 3]),
            (_, Some(g)) => g,
            (_, None) => return Err(format!("{} lies outside any <Piece>", a.label())),
        };
        let tuples = match a.section {
            Section::Point | Section::Points => Some(points),
            Section::Cell => Some(cells),
            Section::Coordinates(axis) => Some(dims[axis.min(2)]),
            Section::Cells => match a.attr("Name") {
                Some("offsets" | "types") => Some(cells),
                Some("connectivity") => last_offset(&arrays, a.piece, appended_text.as_deref(), &encoding)?,
                _ => None,
            },
            Section::Other => None,
        };
        inflated = inflated.saturating_add(vet_array(a, tuples, appended_text.as_deref(), &encoding)?);
        if inflated > INFLATE_CAP {
            return Err(format!(
                "{}: the file's compressed arrays inflate to more than {} together, the most the reader takes",
                a.label(),
                crate::files::size(INFLATE_CAP)
            ));
        }
    }
    Ok(arrays
        .iter()
        .filter_map(|a| match a.section {
            Section::Point => Some((DataAt::Point, a.name())),
            Section::Cell => Some((DataAt::Cell, a.name())),
            _ => None,
        })
        .collect())
}

/// The attributes of an element, unescaped.
fn attributes(e: &BytesStart) -> Result<Vec<(String, String)>, String> {
    let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
    e.attributes()
        .map(|a| {
            let a = a.map_err(|err| format!("<{name}> has a malformed attribute: {err}"))?;
            let key = String::from_utf8_lossy(a.key.local_name().as_ref()).into_owned();
            let value = a
                .unescape_value()
                .map_err(|err| format!("<{name}>'s {key} cannot be read: {err}"))?
                .into_owned();
            Ok((key, value))
        })
        .collect()
}

/// A count written short when large (`1.8e10`), exact below 10⁶.
fn big(n: u64) -> String {
    if n < 1_000_000 { n.to_string() } else { format!("{:.3e}", n as f64) }
}

/// The points, cells (as `vtkio` counts them) and nodes per axis of extent `"x0 x1 y0 y1 z0 z1"`.
fn extent(text: &str) -> Result<(u64, u64, [u64; 3]), String> {
    let v: Vec<i64> = text
        .split_ascii_whitespace()
        .map(str::parse::<i64>)
        .collect::<Result<_, _>>()
        .map_err(|_| "is not six whole numbers".to_string())?;
    let [x0, x1, y0, y1, z0, z1] = v[..] else { return Err("is not six whole numbers".into()) };
    let mut dims = [0u64; 3];
    for (a, (lo, hi)) in [(x0, x1), (y0, y1), (z0, z1)].into_iter().enumerate() {
        let axis = ["x", "y", "z"][a];
        if [lo, hi].iter().any(|v| i32::try_from(*v).is_err()) {
            return Err(format!("holds {lo} … {hi} along {axis}: beyond the 32-bit range VTK extents have"));
        }
        if hi < lo {
            return Err(format!("runs backwards along {axis} ({lo} … {hi})"));
        }
        dims[a] = (hi - lo + 1) as u64;
    }
    let too_many =
        || format!("declares more points than can be counted ({} × {} × {})", dims[0], dims[1], dims[2]);
    let points = dims.iter().try_fold(1u64, |p, &d| p.checked_mul(d)).ok_or_else(too_many)?;
    let cells = dims.iter().try_fold(1u64, |p, &d| p.checked_mul(d - 1)).ok_or_else(too_many)?;
    Ok((points, cells, dims))
}

/// An image's spacing as written: each a positive number that survives `vtkio`'s single
/// precision (a spacing of 1e-300 would be read as 0, and shown as 0).
/// An axis of one node (`dims`) has no spacing to check.
pub fn vet_spacing(key: &str, text: &str, dims: Option<[u64; 3]>) -> Result<(), String> {
    for (a, word) in text.split_ascii_whitespace().enumerate().take(3) {
        let axis = ["x", "y", "z"][a];
        if dims.is_some_and(|d| d[a] == 1) {
            continue;
        }
        let h: f64 =
            word.parse().map_err(|_| format!("{key} \"{text}\": \"{word}\" along {axis} is not a number"))?;
        let single = h as f32;
        if !(h > 0.0 && h.is_finite()) {
            return Err(format!(
                "{key} \"{text}\": {} m along {axis} must be > 0 and finite",
                crate::numeric::num(h)
            ));
        }
        if !single.is_normal() {
            return Err(format!(
                "{key} \"{text}\": {h:e} m along {axis} is beyond single precision ({:e} … {:e} m), \
                 in which VTK image data hold it",
                f32::MIN_POSITIVE,
                f32::MAX
            ));
        }
    }
    Ok(())
}

/// A value type's size, or the refusal naming the array.
fn type_size(a: &Array) -> Result<u64, String> {
    let ty = a.attr("type").ok_or_else(|| format!("{} has no type", a.label()))?;
    TYPES.iter().find(|(n, _)| *n == ty).map(|(_, s)| *s).ok_or_else(|| {
        format!("{} has type \"{ty}\", not one of VTK's ({})", a.label(), TYPES.map(|(n, _)| n).join(", "))
    })
}

fn components(a: &Array) -> Result<u64, String> {
    match a.attr("NumberOfComponents") {
        None => Ok(1),
        Some(t) => match t.trim().parse::<u32>() {
            Ok(n) if n >= 1 => Ok(n as u64),
            _ => Err(format!("{} has NumberOfComponents=\"{t}\", not a count of 1 or more", a.label())),
        },
    }
}

/// Vets one array against its `tuples` (when the grid says how many); the bytes its
/// compressed data inflate to.
fn vet_array(a: &Array, tuples: Option<u64>, appended: Option<&[u8]>, enc: &Encoding) -> Result<u64, String> {
    let label = a.label();
    let size = type_size(a)?;
    let comps = components(a)?;
    let ty = a.attr("type").unwrap_or("");
    let values = match tuples {
        Some(t) => Some(
            t.checked_mul(comps)
                .ok_or_else(|| format!("{label}: {t} tuples × {comps} components overflow"))?,
        ),
        None => None,
    };
    let need_bytes = values.map(|v| v.saturating_mul(size));
    let of_what = |v: u64| match (a.section, tuples) {
        (Section::Cells, _) | (_, None) => format!("{v} values"),
        (Section::Coordinates(_), Some(t)) => format!("the extent's {t} nodes along the axis"),
        (Section::Cell, Some(t)) => format!("its piece's {t} cells × {comps} components"),
        (_, Some(t)) => format!("its piece's {t} points × {comps} components"),
    };
    let format = a.attr("format").unwrap_or("ascii");
    match format {
        "ascii" => {
            let text = a.content();
            let mut count = 0u64;
            for word in text.split(|b| b.is_ascii_whitespace()).filter(|w| !w.is_empty()) {
                if !parses(word, ty) {
                    return Err(format!(
                        "{label}: value {count} \"{}\" is not a number of its type {ty}",
                        String::from_utf8_lossy(&word[..word.len().min(40)])
                    ));
                }
                count += 1;
            }
            if let Some(v) = values
                && count != v
            {
                return Err(format!("{label} holds {count} values; {} need {v}", of_what(v)));
            }
            Ok(0)
        }
        "binary" => {
            let text = a.content();
            if enc.compressed {
                return blocks(&text, need_bytes, enc, &label, size, &of_what, values);
            }
            let bytes = decode(&text).map_err(|e| format!("{label}: its binary data is not base64: {e}"))?;
            let held = (bytes.len() as u64).checked_sub(enc.word).ok_or_else(|| {
                format!("{label}: its binary data ({} bytes) are shorter than their size header", bytes.len())
            })?;
            if let (Some(v), Some(need)) = (values, need_bytes)
                && held != need
            {
                return Err(format!(
                    "{label} holds {held} bytes of {ty} ({} values); {} need {v}, {need} bytes",
                    held / size,
                    of_what(v)
                ));
            }
            Ok(0)
        }
        "appended" => {
            let data =
                appended.ok_or_else(|| format!("{label} is appended but the file has no <AppendedData>"))?;
            let offset_text = a.attr("offset").unwrap_or("0");
            let offset: u64 = offset_text
                .trim()
                .parse()
                .map_err(|_| format!("{label} has offset=\"{offset_text}\", not a count"))?;
            let region = usize::try_from(offset).ok().and_then(|o| data.get(o..)).ok_or_else(|| {
                format!("{label} has offset {offset}, beyond the {} bytes of appended data", data.len())
            })?;
            if enc.compressed {
                return blocks(region, need_bytes, enc, &label, size, &of_what, values);
            }
            let declared = header_word(region, 0, enc).ok_or_else(|| {
                format!("{label}: the appended data end inside its size header (offset {offset})")
            })?;
            if let (Some(v), Some(need)) = (values, need_bytes)
                && declared != need
            {
                return Err(format!(
                    "{label} declares {declared} bytes of {ty} ({} values); {} need {v}, {need} bytes",
                    declared / size,
                    of_what(v)
                ));
            }
            let chars = b64_len(declared.checked_add(enc.word));
            if chars.is_none_or(|c| c > region.len() as u64) {
                return Err(format!(
                    "{label} declares {declared} bytes at offset {offset}; the appended data end before \
                     (the file is cut short or the size is wrong)"
                ));
            }
            Ok(0)
        }
        other => Err(format!("{label} has format \"{other}\": expected ascii, binary or appended")),
    }
}

/// The characters of base64 that encode `bytes` bytes (as `vtkio` counts them).
fn b64_len(bytes: Option<u64>) -> Option<u64> {
    bytes?.div_ceil(3).checked_mul(4)
}

/// Base64 as `vtkio` decodes it (padding, trailing bits allowed).
fn decode(text: &[u8]) -> Result<Vec<u8>, base64::DecodeError> {
    const ENGINE: base64::engine::GeneralPurpose = base64::engine::GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        base64::engine::general_purpose::PAD.with_decode_allow_trailing_bits(true),
    );
    ENGINE.decode(text)
}

/// Header word `i` of base64 `text` whose first `words` words are a separately encoded run.
fn header_words(text: &[u8], words: u64, enc: &Encoding) -> Option<Vec<u64>> {
    let chars = usize::try_from(b64_len(words.checked_mul(enc.word))?).ok()?;
    let bytes = decode(text.get(..chars)?).ok()?;
    let w = enc.word as usize;
    (0..words as usize)
        .map(|i| {
            let b = bytes.get(i * w..(i + 1) * w)?;
            Some(match (w, enc.little) {
                (8, true) => u64::from_le_bytes(b.try_into().ok()?),
                (8, false) => u64::from_be_bytes(b.try_into().ok()?),
                (_, true) => u32::from_le_bytes(b.try_into().ok()?) as u64,
                (_, false) => u32::from_be_bytes(b.try_into().ok()?) as u64,
            })
        })
        .collect()
}

fn header_word(text: &[u8], i: u64, enc: &Encoding) -> Option<u64> {
    header_words(text, i + 1, enc)?.get(i as usize).copied()
}

/// Vets a compressed array's block table in base64 `text` against `need` bytes; the bytes it
/// inflates to.
#[allow(clippy::too_many_arguments)]
fn blocks(
    text: &[u8],
    need: Option<u64>,
    enc: &Encoding,
    label: &str,
    size: u64,
    of_what: &dyn Fn(u64) -> String,
    values: Option<u64>,
) -> Result<u64, String> {
    let nb = header_word(text, 0, enc)
        .ok_or_else(|| format!("{label}: its data end inside their compression header"))?;
    if nb == 0 {
        return Err(format!("{label} declares 0 compressed blocks"));
    }
    // Each block takes a header word at least: a count beyond the text is a lie, caught before
    // the table is read.
    if nb > text.len() as u64 {
        return Err(format!("{label} declares {} compressed blocks in {} characters", big(nb), text.len()));
    }
    let table = header_words(text, 3 + nb, enc)
        .ok_or_else(|| format!("{label}: its data end inside their block table ({nb} blocks declared)"))?;
    let (nu, np) = (table[1], table[2]);
    let compressed = table[3..].iter().try_fold(0u64, |s, &c| s.checked_add(c));
    let header_chars = b64_len((3 + nb).checked_mul(enc.word)).unwrap_or(u64::MAX);
    let present = (text.len() as u64).saturating_sub(header_chars);
    let Some(compressed) = compressed.filter(|&c| b64_len(Some(c)).is_some_and(|chars| chars <= present))
    else {
        return Err(format!(
            "{label} declares {} compressed bytes; the data end before (the file is cut short or the table is wrong)",
            big(table[3..].iter().fold(0u64, |s, &c| s.saturating_add(c)))
        ));
    };
    // VTK: np is the last block's size, 0 when that block is full.
    let inflated = nu
        .checked_mul(nb - if np == 0 { 0 } else { 1 })
        .and_then(|s| s.checked_add(np))
        .ok_or_else(|| format!("{label} declares blocks of {nu} bytes × {nb}: more than can be counted"))?;
    if inflated > INFLATE_CAP {
        return Err(format!(
            "{label} declares {} bytes once inflated, beyond the {} the reader takes",
            big(inflated),
            crate::files::size(INFLATE_CAP)
        ));
    }
    if let (Some(v), Some(need)) = (values, need)
        && inflated != need
    {
        return Err(format!(
            "{label} declares {} bytes once inflated ({} values); {} need {v}, {need} bytes",
            big(inflated),
            big(inflated / size),
            of_what(v)
        ));
    }
    // Each block inflates on its own: an empty block, or one that would inflate beyond
    // zlib's ratio, cannot hold its share (vtkio would drop the array).
    for (b, &nc) in table[3..].iter().enumerate() {
        let share = if b as u64 + 1 == nb && np != 0 { np } else { nu };
        if share > nc.saturating_mul(DEFLATE_RATIO) {
            return Err(format!(
                "{label}: its compressed block {b} of {nb} holds {nc} bytes, which cannot inflate to the {share} \
                 declared (zlib inflates {DEFLATE_RATIO}-fold at most)"
            ));
        }
    }
    if inflated > compressed.saturating_mul(DEFLATE_RATIO) {
        return Err(format!(
            "{label} declares {} bytes from {compressed} compressed bytes: zlib inflates {DEFLATE_RATIO}-fold at most",
            big(inflated)
        ));
    }
    Ok(inflated)
}

/// Whether `word` reads as a number of VTK type `ty` (as `vtkio` reads ASCII data).
fn parses(word: &[u8], ty: &str) -> bool {
    let Ok(s) = std::str::from_utf8(word) else { return false };
    match ty {
        "Int8" => s.parse::<i8>().is_ok(),
        "UInt8" => s.parse::<u8>().is_ok(),
        "Int16" => s.parse::<i16>().is_ok(),
        "UInt16" => s.parse::<u16>().is_ok(),
        "Int32" => s.parse::<i32>().is_ok(),
        "UInt32" => s.parse::<u32>().is_ok(),
        "Int64" => s.parse::<i64>().is_ok(),
        "UInt64" => s.parse::<u64>().is_ok(),
        "Float32" => s.parse::<f32>().is_ok(),
        _ => s.parse::<f64>().is_ok(),
    }
}

/// The connectivity's length: the piece's last offset, when it can be read without inflating
/// (ASCII or uncompressed data; compressed connectivity is bounded by its own block table).
fn last_offset(
    arrays: &[Array],
    piece: usize,
    appended: Option<&[u8]>,
    enc: &Encoding,
) -> Result<Option<u64>, String> {
    let Some(a) = arrays
        .iter()
        .find(|a| a.piece == piece && a.section == Section::Cells && a.attr("Name") == Some("offsets"))
    else {
        return Ok(None);
    };
    let size = type_size(a)?;
    let value = |b: &[u8]| -> Option<u64> {
        let n = size as usize;
        let mut w = [0u8; 8];
        if enc.little {
            w[..n].copy_from_slice(b.get(..n)?);
            Some(u64::from_le_bytes(w))
        } else {
            w[8 - n..].copy_from_slice(b.get(..n)?);
            Some(u64::from_be_bytes(w))
        }
    };
    let last = match a.attr("format").unwrap_or("ascii") {
        "ascii" => {
            let text = a.content();
            text.split(|b| b.is_ascii_whitespace())
                .rfind(|w| !w.is_empty())
                .and_then(|w| std::str::from_utf8(w).ok()?.parse::<u64>().ok())
        }
        _ if enc.compressed => None,
        "binary" => {
            let bytes = decode(&a.content()).ok();
            bytes.and_then(|b| {
                let n = (b.len() as u64).checked_sub(enc.word)? / size;
                (n > 0).then(|| value(&b[(enc.word + (n - 1) * size) as usize..]))?
            })
        }
        "appended" => {
            let offset: Option<usize> = a.attr("offset").and_then(|o| o.trim().parse().ok());
            let region = offset.and_then(|o| appended?.get(o..));
            region.and_then(|r| {
                let declared = header_word(r, 0, enc)?;
                let n = declared / size;
                if n == 0 {
                    return None;
                }
                let chars = usize::try_from(b64_len(declared.checked_add(enc.word))?).ok()?;
                let b = decode(r.get(..chars)?).ok()?;
                value(b.get((enc.word + (n - 1) * size) as usize..)?)
            })
        }
        _ => None,
    };
    Ok(last)
}
