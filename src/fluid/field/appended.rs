//! Raw appended data, which `vtkio` 0.7.0-rc2 cannot read, re-encoded as base64 appended data,
//! which it can. ParaView's XML writers put arrays in a raw `<AppendedData>` block by default,
//! so without this most `.vtu`/`.vti` files saved from ParaView would be refused.
//!
//! Each array's block (its header, then its data: one size word, or for compressed data the
//! block table `[nb][nu][np][nc_1 … nc_nb]` then the compressed blocks) is cut out of the raw
//! bytes at its `offset`, encoded as VTK's base64 appended format expects (the compressed
//! header and the compressed data as two base64 runs), and the offsets are rewritten.

use base64::Engine;
use base64::engine::general_purpose::STANDARD;

/// The file with its raw appended data turned into base64, or `None` if it has none.
pub fn raw_to_base64(file: &[u8]) -> Result<Option<Vec<u8>>, String> {
    let Some(tag) = find(file, b"<AppendedData") else { return Ok(None) };
    let tag_end = find(&file[tag..], b">").map(|i| tag + i).ok_or("an <AppendedData> tag is not closed")?;
    let tag_text = String::from_utf8_lossy(&file[tag..tag_end]);
    if !tag_text.contains("\"raw\"") {
        return Ok(None);
    }
    let start =
        find(&file[tag_end..], b"_").map(|i| tag_end + i + 1).ok_or("raw appended data has no '_' mark")?;
    let end =
        rfind(file, b"</AppendedData>").filter(|&e| e >= start).ok_or("raw appended data is not closed")?;
    let data = &file[start..end];
    let head = String::from_utf8_lossy(&file[..tag]).into_owned();
    let word = if head.contains("header_type=\"UInt64\"") { 8 } else { 4 };
    let compressed = head.contains("compressor=\"vtk");
    let read = |at: usize| -> Result<usize, String> {
        let b = at
            .checked_add(word)
            .and_then(|end| data.get(at..end))
            .ok_or("raw appended data ends inside a block's header")?;
        Ok(if word == 8 {
            u64::from_le_bytes(b.try_into().unwrap_or([0; 8])) as usize
        } else {
            u32::from_le_bytes(b.try_into().unwrap_or([0; 4])) as usize
        })
    };
    if head.contains("byte_order=\"BigEndian\"") {
        return Err("big-endian raw appended data is not supported; save the file little-endian".into());
    }
    // Rewrite every offset="N" in order, encoding each block once.
    let mut out = String::with_capacity(head.len());
    let mut encoded = String::new();
    let mut done: Vec<(usize, usize)> = Vec::new();
    let mut rest = head.as_str();
    while let Some(i) = rest.find("offset=\"") {
        let (before, after) = rest.split_at(i + 8);
        let close = after.find('"').ok_or("an offset attribute is not closed")?;
        let old: usize = after[..close]
            .trim()
            .parse()
            .map_err(|_| format!("offset \"{}\" is not a number", &after[..close]))?;
        let new = match done.iter().find(|(o, _)| *o == old) {
            Some(&(_, n)) => n,
            None => {
                let n = encoded.len();
                if compressed {
                    let blocks = read(old)?;
                    // Checked: a block count read from the file may be anything (2⁶⁴ − 1).
                    let header = blocks
                        .checked_add(3)
                        .and_then(|n| n.checked_mul(word))
                        .and_then(|h| Some((h, old.checked_add(h)?)))
                        .filter(|&(_, end)| end <= data.len());
                    let Some((header, _)) = header else {
                        return Err(format!(
                            "raw appended data ends inside a block table (offset {old} declares {blocks} blocks)"
                        ));
                    };
                    let mut size = 0usize;
                    for b in 0..blocks {
                        size = size.saturating_add(read(old + word * (3 + b))?);
                    }
                    let h =
                        data.get(old..old + header).ok_or("raw appended data ends inside a block table")?;
                    let d = data
                        .get(old + header..old.saturating_add(header).saturating_add(size))
                        .ok_or("raw appended data ends inside a compressed array")?;
                    encoded.push_str(&STANDARD.encode(h));
                    encoded.push_str(&STANDARD.encode(d));
                } else {
                    let size = read(old)?;
                    let block = data
                        .get(old..old.saturating_add(word).saturating_add(size))
                        .ok_or("raw appended data ends inside an array")?;
                    encoded.push_str(&STANDARD.encode(block));
                }
                done.push((old, n));
                n
            }
        };
        out.push_str(before);
        out.push_str(&new.to_string());
        rest = &after[close..];
    }
    out.push_str(rest);
    let mut result = out.into_bytes();
    result.extend_from_slice(b"<AppendedData encoding=\"base64\">\n_");
    result.extend_from_slice(encoded.as_bytes());
    result.extend_from_slice(b"\n");
    result.extend_from_slice(&file[end..]);
    Ok(Some(result))
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn rfind(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}
