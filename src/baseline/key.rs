//! A file's key in a baseline: its normalised path relative to the
//! baseline's directory, `/`-separated, written reversibly (the module doc
//! of `baseline` says how).

use crate::diagnostic::{Error, Result};
use std::path::{Component, Path, PathBuf};

/// The key of a relative path: components joined by `/`; `%` and every byte
/// that is not part of valid UTF-8 written `%XX` (upper-case hex). Reversible
/// by [`decode_key`].
pub fn encode_key(rel: &Path) -> String {
    let mut out = String::new();
    for (i, c) in rel.components().enumerate() {
        if i > 0 {
            out.push('/');
        }
        let part = match c {
            Component::ParentDir => "..".as_ref(),
            Component::CurDir => ".".as_ref(),
            other => other.as_os_str(),
        };
        for chunk in os_bytes(part).utf8_chunks() {
            for ch in chunk.valid().chars() {
                if ch == '%' {
                    out.push_str("%25");
                } else {
                    out.push(ch);
                }
            }
            for b in chunk.invalid() {
                out.push_str(&format!("%{b:02X}"));
            }
        }
    }
    out
}

#[cfg(unix)]
fn os_bytes(s: &std::ffi::OsStr) -> &[u8] {
    std::os::unix::ffi::OsStrExt::as_bytes(s)
}
#[cfg(not(unix))]
fn os_bytes(s: &std::ffi::OsStr) -> &[u8] {
    // Elsewhere file names are Unicode (lossy only for unpaired surrogates).
    s.as_encoded_bytes()
}

/// The relative path a key names (the inverse of [`encode_key`]); `None` when
/// the key is not one [`encode_key`] writes (a `%` not followed by two hex
/// digits).
pub fn decode_key(key: &str) -> Option<PathBuf> {
    let b = key.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    #[cfg(unix)]
    {
        Some(PathBuf::from(
            <std::ffi::OsString as std::os::unix::ffi::OsStringExt>::from_vec(out),
        ))
    }
    #[cfg(not(unix))]
    {
        String::from_utf8(out).ok().map(PathBuf::from)
    }
}

/// `target` relative to `dir` (both absolute and normalised): `..` for each
/// component of `dir` past their common prefix.
pub fn relative_to(target: &Path, dir: &Path) -> PathBuf {
    let t: Vec<Component> = target.components().collect();
    let d: Vec<Component> = dir.components().collect();
    let common = t.iter().zip(&d).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..d.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    out
}

/// Lexical normalisation of an absolute path: `.` dropped, `..` pops.
pub fn normalise(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| Error::io(p, &e))
}

/// The key of `file` in a baseline kept in the directory whose real path is
/// `canon_dir`. `root` is the checked path `file` was found under
/// (`canon_root` its real path): symlinks are resolved when the file they
/// lead to stays inside it; otherwise the file keeps its place in the tree
/// (a link out of the checked root is keyed where it is found).
pub fn key_in(file: &Path, root: &Path, canon_root: &Path, canon_dir: &Path) -> Result<String> {
    let (canon_root, dir) = (canon_root.to_path_buf(), canon_dir);
    let canon = file.canonicalize().map_err(|e| Error::io(file, &e))?;
    let place = if canon.starts_with(&canon_root) {
        canon
    } else {
        // The link leaves the root: keep the path as found under the root.
        let rel = normalise(&absolute(file)?);
        let abs_root = normalise(&absolute(root)?);
        match rel.strip_prefix(&abs_root) {
            Ok(tail) => canon_root.join(tail),
            Err(_) => canon,
        }
    };
    Ok(encode_key(&relative_to(&place, dir)))
}
