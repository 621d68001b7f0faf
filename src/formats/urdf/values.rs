//! Attribute values as written and as XML reads them: one scan of the text
//! notes everything the reader asks of a value ([`Scan`]), and only a value
//! with an entity or a literal tab or line break is decoded into a new string.

use std::borrow::Cow;

/// What one pass over an attribute value's text found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Scan {
    /// No `&`, tab, CR or LF: the value is the text as written.
    pub plain: bool,
    /// A `<` (refused by roxmltree, let through by quick-xml).
    pub lt: bool,
    /// A character reference `&#` (checked by roxmltree).
    pub char_ref: bool,
    /// A xacro expression or substitution, `${` or `$(` (in the text; a value
    /// that is not plain is checked again once decoded, see [`has_expr`]).
    pub expr: bool,
}

/// One pass over `raw`.
pub(super) fn scan(raw: &str) -> Scan {
    let b = raw.as_bytes();
    let mut s = Scan {
        plain: true,
        lt: false,
        char_ref: false,
        expr: false,
    };
    for (i, &c) in b.iter().enumerate() {
        match c {
            b'&' => {
                s.plain = false;
                s.char_ref |= b.get(i + 1) == Some(&b'#');
            }
            b'\t' | b'\n' | b'\r' => s.plain = false,
            b'<' => s.lt = true,
            b'$' => s.expr |= matches!(b.get(i + 1), Some(b'{' | b'(')),
            _ => {}
        }
    }
    s
}

/// `${` or `$(` in a decoded value.
pub(super) fn has_expr(value: &str) -> bool {
    value.contains("${") || value.contains("$(")
}

/// The character an entity or character reference stands for.
fn entity(name: &str) -> Option<char> {
    let code = if let Some(h) = name.strip_prefix("#x") {
        u32::from_str_radix(h, 16).ok()?
    } else if let Some(d) = name.strip_prefix('#') {
        d.parse().ok()?
    } else {
        return match name {
            "lt" => Some('<'),
            "gt" => Some('>'),
            "amp" => Some('&'),
            "apos" => Some('\''),
            "quot" => Some('"'),
            _ => None,
        };
    };
    char::from_u32(code)
}

/// An attribute value as XML reads it: literal tab, CR, LF (a CR LF pair
/// counting once) become spaces; the five predefined entities and character
/// references are replaced (a reference's character is kept as is). `None`
/// for any other entity.
pub(super) fn decode(raw: &str) -> Option<Cow<'_, str>> {
    if !raw.contains(['&', '\t', '\n', '\r']) {
        return Some(Cow::Borrowed(raw));
    }
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(i) = rest.find(['&', '\t', '\n', '\r']) {
        out.push_str(&rest[..i]);
        let tail = &rest[i..];
        if let Some(t) = tail.strip_prefix("\r\n") {
            out.push(' ');
            rest = t;
        } else if tail.starts_with('&') {
            let end = tail.find(';')?;
            out.push(entity(&tail[1..end])?);
            rest = &tail[end + 1..];
        } else {
            out.push(' ');
            rest = &tail[1..];
        }
    }
    out.push_str(rest);
    Some(Cow::Owned(out))
}

#[cfg(test)]
mod tests {
    use super::{decode, has_expr, scan, Scan};

    #[test]
    fn attribute_values_decode_as_xml_reads_them() {
        assert_eq!(decode("a b").unwrap(), "a b");
        assert_eq!(decode("a\tb\r\nc\rd\ne").unwrap(), "a b c d e");
        assert_eq!(decode("&lt;&amp;&gt;&apos;&quot;").unwrap(), "<&>'\"");
        assert_eq!(decode("a&#9;b&#x41;").unwrap(), "a\tbA");
        assert!(decode("&nbsp;").is_none());
        assert!(decode("a & b").is_none());
    }

    /// One scan finds what the separate searches of the text found
    /// (`contains` of each marker), on every value of a small alphabet.
    #[test]
    fn one_scan_finds_every_marker() {
        let alphabet = [
            "a", "1", " ", "&", "#", "<", "$", "{", "(", "\t", "\n", "\r",
        ];
        let mut values = vec![String::new()];
        for _ in 0..3 {
            let next: Vec<String> = values
                .iter()
                .flat_map(|v| alphabet.iter().map(move |c| format!("{v}{c}")))
                .collect();
            values.extend(next);
        }
        for v in &values {
            let want = Scan {
                plain: !v.contains(['&', '\t', '\n', '\r']),
                lt: v.contains('<'),
                char_ref: v.contains("&#"),
                expr: has_expr(v),
            };
            assert_eq!(scan(v), want, "{v:?}");
        }
        assert!(scan("${x} 1 2").expr && scan("$(arg a)").expr && !scan("$ {x}").expr);
        assert!(!scan("0.1 -2e-3 +4E+5").expr && scan("0.1 -2e-3 +4E+5").plain);
    }
}
