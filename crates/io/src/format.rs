//! File formats: choice by extension, with a content sniff as fallback.

use std::fmt;
use std::path::Path;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ (text).
    Obj,
    /// Stanford PLY (ascii or binary, either endianness).
    Ply,
    /// STL (ascii or binary).
    Stl,
    /// Object File Format (text).
    Off,
    /// glTF 2.0 JSON (`.gltf`), buffers embedded as data URIs or in files beside it.
    Gltf,
    /// Binary glTF 2.0 (`.glb`).
    Glb,
}

impl Format {
    /// All formats, in a fixed order.
    pub const ALL: [Format; 6] = [
        Format::Obj,
        Format::Ply,
        Format::Stl,
        Format::Off,
        Format::Gltf,
        Format::Glb,
    ];

    /// The usual file extension (lower case, no dot).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Ply => "ply",
            Format::Stl => "stl",
            Format::Off => "off",
            Format::Gltf => "gltf",
            Format::Glb => "glb",
        }
    }

    /// The format named by a file extension (case-insensitive, without the dot).
    pub fn from_extension(ext: &str) -> Option<Format> {
        let ext = ext.to_ascii_lowercase();
        Format::ALL.into_iter().find(|f| f.extension() == ext)
    }

    /// The format named by the extension of `path`, if any.
    pub fn from_path(path: &Path) -> Option<Format> {
        path.extension()
            .and_then(|e| e.to_str())
            .and_then(Format::from_extension)
    }

    /// Guesses the format from the first bytes (or all) of a file's content.
    ///
    /// Recognises the PLY and glTF magic numbers, OFF headers, ascii STL (`solid` followed by
    /// `facet`), binary STL (length = 84 + 50 × triangle count), glTF JSON (`{` ... `"asset"`)
    /// and OBJ statements (`v`, `vn`, `f`, ...).
    pub fn sniff(bytes: &[u8]) -> Option<Format> {
        if bytes.starts_with(b"glTF") {
            return Some(Format::Glb);
        }
        if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
            return Some(Format::Ply);
        }
        if bytes.len() >= 84 {
            let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
            if 84 + 50 * n == bytes.len() as u64 {
                return Some(Format::Stl);
            }
        }
        let text_bytes = crate::without_bom(bytes);
        let head = &text_bytes[..text_bytes.len().min(4096)];
        let text = String::from_utf8_lossy(head);
        let trimmed = text.trim_start();
        if trimmed.starts_with('{') && text.contains("\"asset\"") {
            return Some(Format::Gltf);
        }
        if trimmed.starts_with("solid") && text.contains("facet") {
            return Some(Format::Stl);
        }
        let first = trimmed.split_whitespace().next().unwrap_or("");
        if crate::off::is_off_keyword(first) {
            return Some(Format::Off);
        }
        let mut obj_statements = 0;
        for line in text.lines() {
            let key = line.split_whitespace().next().unwrap_or("");
            match key {
                "v" | "vn" | "vt" | "f" | "g" | "o" | "usemtl" | "mtllib" | "s" => {
                    obj_statements += 1
                }
                "" => {}
                k if k.starts_with('#') => {}
                _ => return None,
            }
        }
        (obj_statements > 0).then_some(Format::Obj)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Stl => "STL",
            Format::Off => "OFF",
            Format::Gltf => "glTF",
            Format::Glb => "GLB",
        })
    }
}
