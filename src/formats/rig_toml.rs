//! The tool's own TOML rig format (`calibrations/*.toml`; specification in
//! `docs/rig-format.md`, a commented example in `calibrations/README.md`).
//!
//! A rig file carries provenance (`[rig]`: id, sensor, platform, dataset, source
//! repository/path/commit, licence, direction convention, placeholder flag, the
//! body frame `from` and LiDAR frame `to` the survey uses) and one or more
//! `[[transform]]` edges with the numbers exactly as published:
//!
//! ```toml
//! [rig]
//! id = "fastlio-avia"
//! # ... metadata ...
//! from = "imu"
//! to = "lidar"
//! [rig.source]
//! repo = "hku-mars/FAST_LIO"
//! path = "config/avia.yaml"
//! commit = "7cc4175de6f8ba2edf34bab02a42195b141027e9"
//!
//! [[transform]]
//! parent = "imu"
//! child = "lidar"
//! unit = "m"
//! translation = [0.04165, 0.02326, -0.0284]
//! rotation_matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
//! source_key = "mapping.extrinsic_T + mapping.extrinsic_R"
//! ```
//!
//! Every edge is `parent -> child` with the transform = pose of `child` in
//! `parent` (`p_parent = R p_child + t`). When the source publishes the other
//! direction, the numbers stay as written and `invert = true` says so. Exactly one
//! rotation form per edge. A chain (several edges) is composed by the frame graph.
//! `[[include]]` loads a raw file lying beside the TOML (sidecar mode) as
//! `formats::load_file` loads any file (`Input::includes`).
//!
//! TOML numbers are parsed to `f64` exactly as every other loader parses decimal
//! text (round to nearest), so writing the published digits reproduces the
//! published value. Integers (`1`, `0`) are accepted wherever a number is.
//!
//! Errors name the file and line (from the TOML parser's span), what was expected
//! and what was found. The parser never panics on any input.

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::source::{line_col, LineIndex};
use crate::formats::spec::{FormatSpec, Includes, LoadOptions, Parsed, RigMeta};
use crate::formats::toml_subset::{self, Header, Table, Value};
use crate::frames::{Edge, Provenance, ValuesAt};
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{rounding_covariance, tuple_half_units};
use crate::geometry::{EdgePrecision, UserSigma};
use crate::tolerances::{MAX_SIGMA_R_DEG, MAX_SIGMA_T_M};
use serde::Deserialize;
use std::collections::BTreeSet;
use std::ops::Range;
use std::path::{Component, Path, PathBuf};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// Values `[rig] category` may take.
pub const CATEGORIES: [&str; 5] = [
    "factory",
    "dataset-calibration",
    "cad-or-nominal",
    "third-party-config",
    "placeholder",
];

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RigFile {
    rig: Spanned<RigTable>,
    #[serde(default)]
    transform: Vec<Spanned<TransformDef>>,
    #[serde(default)]
    include: Vec<Spanned<IncludeDef>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RigTable {
    id: String,
    sensor: String,
    platform: String,
    dataset: String,
    category: String,
    licence: String,
    direction: String,
    #[serde(default)]
    placeholder: bool,
    #[serde(default)]
    notes: Option<String>,
    from: String,
    to: String,
    #[serde(default)]
    duplicate_of: Option<String>,
    /// The calibration's standard uncertainty per edge (m), for every edge of
    /// this file (`--sigma-t` for the others).
    #[serde(default)]
    sigma_t_m: Option<f64>,
    /// The same for rotation (degrees).
    #[serde(default)]
    sigma_r_deg: Option<f64>,
    source: SourceTable,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SourceTable {
    repo: String,
    path: String,
    commit: String,
    #[serde(default)]
    url: Option<String>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "lowercase")]
enum Unit {
    M,
    Mm,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisAngle {
    axis: [f64; 3],
    /// Radians.
    angle: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct TransformDef {
    parent: String,
    child: String,
    unit: Unit,
    #[serde(default)]
    translation: Option<[f64; 3]>,
    #[serde(default)]
    rotation_matrix: Option<[[f64; 3]; 3]>,
    #[serde(default)]
    quaternion_xyzw: Option<[f64; 4]>,
    #[serde(default)]
    quaternion_wxyz: Option<[f64; 4]>,
    #[serde(default)]
    rpy: Option<[f64; 3]>,
    #[serde(default)]
    ypr: Option<[f64; 3]>,
    #[serde(default)]
    axis_angle: Option<AxisAngle>,
    #[serde(default)]
    matrix4: Option<[[f64; 4]; 4]>,
    #[serde(default)]
    matrix3x4: Option<[[f64; 4]; 3]>,
    #[serde(default)]
    invert: bool,
    source_key: String,
    /// Free text for readers of the file (e.g. how a source expression was
    /// evaluated); parsed so that a typo elsewhere is still refused.
    #[serde(default)]
    #[allow(dead_code)]
    note: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct IncludeDef {
    file: String,
    #[serde(default)]
    key: Option<String>,
    #[serde(default)]
    invert: bool,
    /// Free text for readers of the file.
    #[serde(default)]
    #[allow(dead_code)]
    note: Option<String>,
}

/// The numbers of a `[[transform]]` and how they are read: all an edge is
/// built from, copied for each step of its rounding's derivative (no
/// strings: cloning the whole definition per step was a cost of its own).
#[derive(Debug, Clone, Copy)]
struct Numbers {
    unit: Unit,
    invert: bool,
    translation: Option<[f64; 3]>,
    rotation_matrix: Option<[[f64; 3]; 3]>,
    quaternion_xyzw: Option<[f64; 4]>,
    quaternion_wxyz: Option<[f64; 4]>,
    rpy: Option<[f64; 3]>,
    ypr: Option<[f64; 3]>,
    axis_angle: Option<([f64; 3], f64)>,
    matrix4: Option<[[f64; 4]; 4]>,
    matrix3x4: Option<[[f64; 4]; 3]>,
}

impl Numbers {
    fn of(def: &TransformDef) -> Self {
        Numbers {
            unit: def.unit,
            invert: def.invert,
            translation: def.translation,
            rotation_matrix: def.rotation_matrix,
            quaternion_xyzw: def.quaternion_xyzw,
            quaternion_wxyz: def.quaternion_wxyz,
            rpy: def.rpy,
            ypr: def.ypr,
            axis_angle: def.axis_angle.as_ref().map(|a| (a.axis, a.angle)),
            matrix4: def.matrix4,
            matrix3x4: def.matrix3x4,
        }
    }

    /// The rotation form's numbers as tuples, in [`LiteralSpans::rotation_tuples`]'s
    /// order (one per form; axis-angle two).
    fn rotation_tuples(&self) -> Vec<Vec<f64>> {
        if let Some((axis, angle)) = self.axis_angle {
            return vec![axis.to_vec(), vec![angle]];
        }
        [
            self.rotation_matrix.as_ref().map(|m| m.as_flattened()),
            self.quaternion_xyzw.as_ref().map(|q| &q[..]),
            self.quaternion_wxyz.as_ref().map(|q| &q[..]),
            self.rpy.as_ref().map(|q| &q[..]),
            self.ypr.as_ref().map(|q| &q[..]),
            self.matrix4.as_ref().map(|m| m.as_flattened()),
            self.matrix3x4.as_ref().map(|m| m.as_flattened()),
        ]
        .into_iter()
        .flatten()
        .map(<[f64]>::to_vec)
        .collect()
    }
}

fn loc_of(lines: &LineIndex, path: &Path, offset: usize) -> Location {
    let (l, c) = lines.pos(offset);
    Location::at(path, l, Some(c))
}

/// Parse a rig TOML file. `path` is used for messages and to resolve
/// `[[include]]` files (relative to the TOML's directory); an include is an
/// error here: a rig file read on its own cannot load the files it names
/// (`formats::load_file` can).
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    read(text, path, opts, None)
}

/// [`parse`], loading `[[include]]` files through `includes`.
fn read(
    text: &str,
    path: &Path,
    opts: &LoadOptions,
    includes: Option<&dyn Includes>,
) -> Result<Parsed> {
    // The plain TOML rig files are written in is read by the subset reader;
    // anything else (and every error) by the toml crate.
    let (file, literals) = match read_subset(text) {
        Some(read) => read,
        None => read_toml(text, path)?,
    };

    let mut warnings = Vec::new();
    if opts.invert || opts.key.is_some() {
        warnings.push(
            Warning::new(
                Code::Ignored,
                "--invert and --key do not apply to a rig TOML file: each [[transform]] states its own direction (invert = true) and source_key",
            )
            .at(&Location::file(path)),
        );
    }

    // Every location of a file from one index of its lines (a lookup from
    // the start of the text each was a twentieth of a check, issue 29).
    let lines = LineIndex::new(text);
    let rig_loc = loc_of(&lines, path, file.rig.span().start);
    let rig = file.rig.into_inner();
    let user = user_sigma(&rig, &rig_loc)?;
    let meta = check_rig(rig, &rig_loc)?;

    if file.transform.is_empty() && file.include.is_empty() {
        return Err(Error::parse(
            "rig TOML: expected at least one [[transform]] or [[include]], found none",
        )
        .at(&rig_loc));
    }

    let mut edges = Vec::new();
    for (i, spanned) in file.transform.into_iter().enumerate() {
        let loc = loc_of(&lines, path, spanned.span().start);
        let def = spanned.into_inner();
        let mut w = Vec::new();
        let precision = literals
            .get(i)
            .map(|l| precision_of(i + 1, &Numbers::of(&def), l, text))
            .unwrap_or_default();
        let values = literals
            .get(i)
            .map(|l| l.values_at(&lines))
            .unwrap_or_default();
        let edge = build_edge(i + 1, def, &loc, &mut w)
            .map_err(|e| e.at(&loc))?
            .with_precision(precision)
            .with_values(values);
        warnings.extend(w.into_iter().map(|x| x.at(&loc)));
        edges.push(edge);
    }

    for spanned in file.include {
        let loc = loc_of(&lines, path, spanned.span().start);
        let inc = spanned.into_inner();
        let loaded = load_include(&inc, path, includes, &loc)?;
        warnings.extend(loaded.warnings);
        edges.extend(loaded.edges);
    }
    if let Some(u) = user {
        for e in &mut edges {
            e.precision.user = Some(u);
        }
    }

    // The survey frames must exist among the edges.
    let frames: BTreeSet<&str> = edges
        .iter()
        .flat_map(|e| [e.parent.as_str(), e.child.as_str()])
        .collect();
    for (what, name) in [("from", &meta.from), ("to", &meta.to)] {
        if !frames.contains(name.as_str()) {
            let known: Vec<&str> = frames.iter().copied().collect();
            return Err(Error::frame(format!(
                "rig TOML: [rig] {what} = \"{name}\": expected a frame named by a [[transform]] or an included file, found only {known:?}"
            ))
            .at(&rig_loc));
        }
    }

    Ok(Parsed {
        edges,
        warnings,
        rig: Some(meta),
        ..Parsed::default()
    })
}

/// The typed file and its numbers' spans, by the toml crate.
fn read_toml(text: &str, path: &Path) -> Result<(RigFile, Vec<LiteralSpans>)> {
    // Parsed once: the typed file and the numbers' spans are both read from
    // the one document (lexing and parsing are most of a rig file's cost);
    // the spans by reference, before the typed reading consumes it.
    let doc = DeTable::parse(text);
    let literals: Vec<LiteralSpans> = doc
        .as_ref()
        .ok()
        .and_then(|d| literal_spans(d.get_ref()))
        .unwrap_or_default();
    let file: RigFile = doc
        .and_then(|d| RigFile::deserialize(toml::de::Deserializer::from(d)))
        .map_err(|e| {
            let mut err = Error::parse(format!("rig TOML: {}", e.message().trim_end()));
            err = err.in_file(path);
            if let Some(span) = e.span() {
                let (l, c) = line_col(text, span.start);
                err = err.at_line(l, Some(c));
            }
            err
        })?;
    Ok((file, literals))
}

/// The typed file and its numbers' spans by the subset reader
/// (`toml_subset`): `None` when the text is not in the subset or does not
/// make a rig file as [`read_toml`] types it (which then reads it and says
/// why). Spans as the toml crate gives them: a table's is its header's.
fn read_subset(text: &str) -> Option<(RigFile, Vec<LiteralSpans>)> {
    let tables = toml_subset::parse(text)?;
    let (mut rig, mut source) = (None, None);
    let (mut transform, mut include, mut literals) = (Vec::new(), Vec::new(), Vec::new());
    for t in &tables {
        match t.header {
            Header::Root if t.entries.is_empty() => {}
            Header::Rig if rig.is_none() => rig = Some(t),
            Header::RigSource if source.is_none() && rig.is_some() => source = Some(t),
            Header::Transform => {
                let (def, lits) = subset_transform(t)?;
                transform.push(Spanned::new(t.span.clone(), def));
                literals.push(lits);
            }
            Header::Include => include.push(Spanned::new(t.span.clone(), subset_include(t)?)),
            _ => return None,
        }
    }
    let rig = rig?;
    let table = subset_rig(rig, source?)?;
    let file = RigFile {
        rig: Spanned::new(rig.span.clone(), table),
        transform,
        include,
    };
    Some((file, literals))
}

fn subset_text(v: &Value) -> Option<String> {
    match v {
        Value::Str(s) => Some(s.to_string()),
        _ => None,
    }
}

fn subset_flag(v: &Value) -> Option<bool> {
    match v {
        Value::Bool(b) => Some(*b),
        _ => None,
    }
}

fn subset_number(v: &Value) -> Option<f64> {
    match v {
        Value::Num(x, _) => Some(*x),
        _ => None,
    }
}

/// `N` numbers, their spans appended to `spans`.
fn subset_numbers<const N: usize>(v: &Value, spans: &mut Vec<Range<usize>>) -> Option<[f64; N]> {
    let Value::Array(xs) = v else {
        return None;
    };
    if xs.len() != N {
        return None;
    }
    let mut out = [0.0; N];
    for (o, x) in out.iter_mut().zip(xs) {
        let Value::Num(n, span) = x else {
            return None;
        };
        *o = *n;
        spans.push(span.clone());
    }
    Some(out)
}

/// `R` rows of `C` numbers, into `slot` with their spans (row after row).
fn subset_rows<const R: usize, const C: usize>(
    v: &Value,
    slot: &mut Option<Vec<Range<usize>>>,
) -> Option<[[f64; C]; R]> {
    let Value::Array(rows) = v else {
        return None;
    };
    if rows.len() != R {
        return None;
    }
    let spans = slot.insert(Vec::with_capacity(R * C));
    let mut out = [[0.0; C]; R];
    for (o, row) in out.iter_mut().zip(rows) {
        *o = subset_numbers::<C>(row, spans)?;
    }
    Some(out)
}

/// `N` numbers into `slot` with their spans.
fn subset_tuple<const N: usize>(
    v: &Value,
    slot: &mut Option<Vec<Range<usize>>>,
) -> Option<[f64; N]> {
    subset_numbers::<N>(v, slot.insert(Vec::with_capacity(N)))
}

fn subset_rig(rig: &Table, source: &Table) -> Option<RigTable> {
    const TEXTS: [&str; 11] = [
        "id",
        "sensor",
        "platform",
        "dataset",
        "category",
        "licence",
        "direction",
        "from",
        "to",
        "notes",
        "duplicate_of",
    ];
    let mut s: [Option<String>; 11] = Default::default();
    let (mut placeholder, mut sigma_t_m, mut sigma_r_deg) = (None, None, None);
    // A key appears once per table (the subset reader refuses a second).
    for (k, v) in &rig.entries {
        if let Some(i) = TEXTS.iter().position(|n| n == k) {
            s[i] = Some(subset_text(v)?);
            continue;
        }
        match *k {
            "placeholder" => placeholder = Some(subset_flag(v)?),
            "sigma_t_m" => sigma_t_m = Some(subset_number(v)?),
            "sigma_r_deg" => sigma_r_deg = Some(subset_number(v)?),
            _ => return None,
        }
    }
    let mut src: [Option<String>; 4] = Default::default();
    for (k, v) in &source.entries {
        let i = ["repo", "path", "commit", "url"]
            .iter()
            .position(|n| n == k)?;
        src[i] = Some(subset_text(v)?);
    }
    let [id, sensor, platform, dataset, category, licence, direction, from, to, notes, duplicate_of] =
        s;
    let [repo, path, commit, url] = src;
    Some(RigTable {
        id: id?,
        sensor: sensor?,
        platform: platform?,
        dataset: dataset?,
        category: category?,
        licence: licence?,
        direction: direction?,
        placeholder: placeholder.unwrap_or(false),
        notes,
        from: from?,
        to: to?,
        duplicate_of,
        sigma_t_m,
        sigma_r_deg,
        source: SourceTable {
            repo: repo?,
            path: path?,
            commit: commit?,
            url,
        },
    })
}

fn subset_transform(t: &Table) -> Option<(TransformDef, LiteralSpans)> {
    let mut l = LiteralSpans::default();
    let mut d = TransformDef {
        parent: String::new(),
        child: String::new(),
        unit: Unit::M,
        translation: None,
        rotation_matrix: None,
        quaternion_xyzw: None,
        quaternion_wxyz: None,
        rpy: None,
        ypr: None,
        axis_angle: None,
        matrix4: None,
        matrix3x4: None,
        invert: false,
        source_key: String::new(),
        note: None,
    };
    let (mut parent, mut child, mut unit, mut source_key) = (None, None, None, None);
    for (k, v) in &t.entries {
        match *k {
            "parent" => parent = Some(subset_text(v)?),
            "child" => child = Some(subset_text(v)?),
            "unit" => {
                unit = Some(match v {
                    Value::Str(s) if s == "m" => Unit::M,
                    Value::Str(s) if s == "mm" => Unit::Mm,
                    _ => return None,
                })
            }
            "translation" => d.translation = Some(subset_tuple::<3>(v, &mut l.translation)?),
            "rotation_matrix" => {
                d.rotation_matrix = Some(subset_rows::<3, 3>(v, &mut l.rotation_matrix)?)
            }
            "quaternion_xyzw" => {
                d.quaternion_xyzw = Some(subset_tuple::<4>(v, &mut l.quaternion_xyzw)?)
            }
            "quaternion_wxyz" => {
                d.quaternion_wxyz = Some(subset_tuple::<4>(v, &mut l.quaternion_wxyz)?)
            }
            "rpy" => d.rpy = Some(subset_tuple::<3>(v, &mut l.rpy)?),
            "ypr" => d.ypr = Some(subset_tuple::<3>(v, &mut l.ypr)?),
            "matrix4" => d.matrix4 = Some(subset_rows::<4, 4>(v, &mut l.matrix4)?),
            "matrix3x4" => d.matrix3x4 = Some(subset_rows::<3, 4>(v, &mut l.matrix3x4)?),
            "invert" => d.invert = subset_flag(v)?,
            "source_key" => source_key = Some(subset_text(v)?),
            "note" => d.note = Some(subset_text(v)?),
            // `axis_angle` is an inline table: not in the subset.
            _ => return None,
        }
    }
    d.parent = parent?;
    d.child = child?;
    d.unit = unit?;
    d.source_key = source_key?;
    Some((d, l))
}

fn subset_include(t: &Table) -> Option<IncludeDef> {
    let (mut file, mut key, mut invert, mut note) = (None, None, false, None);
    for (k, v) in &t.entries {
        match *k {
            "file" => file = Some(subset_text(v)?),
            "key" => key = Some(subset_text(v)?),
            "invert" => invert = subset_flag(v)?,
            "note" => note = Some(subset_text(v)?),
            _ => return None,
        }
    }
    Some(IncludeDef {
        file: file?,
        key,
        invert,
        note,
    })
}

/// `what` is formatted only when the string is empty (a message built for
/// every transform that passes cost more than the check).
fn nonempty(what: impl std::fmt::Display, s: &str, loc: &Location) -> Result<()> {
    if s.trim().is_empty() {
        return Err(Error::parse(format!(
            "rig TOML: {what}: expected a non-empty string, found \"\""
        ))
        .at(loc));
    }
    Ok(())
}

fn check_rig(rig: RigTable, loc: &Location) -> Result<RigMeta> {
    for (what, s) in [
        ("[rig] id", &rig.id),
        ("[rig] sensor", &rig.sensor),
        ("[rig] platform", &rig.platform),
        ("[rig] dataset", &rig.dataset),
        ("[rig] licence", &rig.licence),
        ("[rig] direction", &rig.direction),
        ("[rig] from", &rig.from),
        ("[rig] to", &rig.to),
        ("[rig.source] repo", &rig.source.repo),
        ("[rig.source] path", &rig.source.path),
        ("[rig.source] commit", &rig.source.commit),
    ] {
        nonempty(what, s, loc)?;
    }
    if !CATEGORIES.contains(&rig.category.as_str()) {
        return Err(Error::parse(format!(
            "rig TOML: [rig] category: expected one of {CATEGORIES:?}, found \"{}\"",
            rig.category
        ))
        .at(loc));
    }
    if rig.from == rig.to {
        return Err(Error::frame(format!(
            "rig TOML: [rig] from and to: expected two different frames, found \"{}\" twice",
            rig.from
        ))
        .at(loc));
    }
    Ok(RigMeta {
        id: rig.id,
        sensor: rig.sensor,
        platform: rig.platform,
        dataset: rig.dataset,
        from: rig.from,
        to: rig.to,
        source_repo: rig.source.repo,
        source_path: rig.source.path,
        source_commit: rig.source.commit,
        licence: rig.licence,
        direction: rig.direction,
        placeholder: rig.placeholder,
        category: rig.category,
        notes: rig.notes.unwrap_or_default(),
        source_url: rig.source.url,
        duplicate_of: rig.duplicate_of,
    })
}

fn check_finite(index: usize, what: &str, xs: &[f64]) -> Result<()> {
    if let Some(x) = xs.iter().find(|x| !x.is_finite()) {
        return Err(Error::invalid(format!(
            "rig TOML: [[transform]] #{index} {what}: expected finite numbers, found {x}"
        )));
    }
    Ok(())
}

fn build_edge(
    index: usize,
    def: TransformDef,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) -> Result<Edge> {
    nonempty(
        format_args!("[[transform]] #{index} parent"),
        &def.parent,
        loc,
    )?;
    nonempty(
        format_args!("[[transform]] #{index} child"),
        &def.child,
        loc,
    )?;
    nonempty(
        format_args!("[[transform]] #{index} source_key"),
        &def.source_key,
        loc,
    )?;
    if def.parent == def.child {
        return Err(Error::frame(format!(
            "rig TOML: [[transform]] #{index}: expected parent and child to differ, found \"{}\" for both",
            def.parent
        )));
    }

    let form = rotation_form(index, &def)?;
    let carries_translation = matches!(form, "matrix4" | "matrix3x4");
    let d = match (carries_translation, def.translation) {
        (true, Some(_)) => {
            return Err(Error::parse(format!(
                "rig TOML: [[transform]] #{index}: {form} carries the translation in its last column; expected no separate `translation`, found one"
            )))
        }
        (true, None) => [0.0; 3],
        (false, Some(t)) => t,
        (false, None) => {
            return Err(Error::parse(format!(
                "rig TOML: [[transform]] #{index} ({} -> {}): expected `translation = [x, y, z]` with {form}, found none",
                def.parent, def.child
            )))
        }
    };
    check_finite(index, "translation", &d)?;

    let t = rotation(index, &Numbers::of(&def), d, Some(warnings))?;
    let t = match def.unit {
        Unit::M => t,
        Unit::Mm => t.scaled_translation(1e-3),
    };
    let t = if def.invert { t.inverse() } else { t };

    let mut key = def.source_key;
    if def.invert {
        key.push_str(" (inverted: published as the pose of the parent in the child)");
    }
    Ok(Edge {
        parent: def.parent,
        child: def.child,
        transform: t,
        provenance: Provenance {
            location: loc.clone(),
            format: SPEC.id,
            key,
            values: Default::default(),
        },
        joint: None,
        precision: Default::default(),
    })
}

/// The one rotation form a `[[transform]]` gives (none or several: an error).
fn rotation_form(index: usize, def: &TransformDef) -> Result<&'static str> {
    let mut forms: Vec<&'static str> = Vec::new();
    if def.rotation_matrix.is_some() {
        forms.push("rotation_matrix");
    }
    if def.quaternion_xyzw.is_some() {
        forms.push("quaternion_xyzw");
    }
    if def.quaternion_wxyz.is_some() {
        forms.push("quaternion_wxyz");
    }
    if def.rpy.is_some() {
        forms.push("rpy");
    }
    if def.ypr.is_some() {
        forms.push("ypr");
    }
    if def.axis_angle.is_some() {
        forms.push("axis_angle");
    }
    if def.matrix4.is_some() {
        forms.push("matrix4");
    }
    if def.matrix3x4.is_some() {
        forms.push("matrix3x4");
    }
    const FORMS: &str = "rotation_matrix, quaternion_xyzw, quaternion_wxyz, rpy, ypr, axis_angle, matrix4 or matrix3x4";
    match forms.len() {
        0 => Err(Error::parse(format!(
                "rig TOML: [[transform]] #{index} ({} -> {}): expected exactly one rotation form ({FORMS}), found none",
                def.parent, def.child
            ))),
        1 => Ok(forms[0]),
        _ => Err(Error::parse(format!(
                "rig TOML: [[transform]] #{index} ({} -> {}): expected exactly one rotation form ({FORMS}), found {}",
                def.parent,
                def.child,
                forms.join(" and ")
            ))),
    }
}

/// The transform from the one rotation form given and translation `d`;
/// `warnings: None` for a derivative's step, whose warnings nobody reads
/// (the matrix forms then skip formatting them).
fn rotation(
    index: usize,
    def: &Numbers,
    d: [f64; 3],
    warnings: Option<&mut Vec<Warning>>,
) -> Result<Transform> {
    let mut dropped = Vec::new();
    let quiet = warnings.is_none();
    let warnings = warnings.unwrap_or(&mut dropped);
    if let Some(r) = def.rotation_matrix {
        check_finite(index, "rotation_matrix", r.as_flattened())?;
        if quiet {
            return Transform::from_matrix3_quiet(r, d);
        }
        Transform::from_matrix3(r, d, warnings)
    } else if let Some(q) = def.quaternion_xyzw {
        check_finite(index, "quaternion_xyzw", &q)?;
        Transform::from_quaternion(q, QuatOrder::Xyzw, d, warnings)
    } else if let Some(q) = def.quaternion_wxyz {
        check_finite(index, "quaternion_wxyz", &q)?;
        Transform::from_quaternion(q, QuatOrder::Wxyz, d, warnings)
    } else if let Some(a) = def.rpy {
        check_finite(index, "rpy", &a)?;
        Transform::from_rpy(a, d)
    } else if let Some(a) = def.ypr {
        check_finite(index, "ypr", &a)?;
        Transform::from_ypr(a, d)
    } else if let Some((axis, angle)) = def.axis_angle {
        check_finite(index, "axis_angle.axis", &axis)?;
        check_finite(index, "axis_angle.angle", &[angle])?;
        Transform::from_axis_angle(axis, angle, d)
    } else if let Some(m) = def.matrix4 {
        check_finite(index, "matrix4", m.as_flattened())?;
        if quiet {
            return Transform::from_matrix4_quiet(m);
        }
        Transform::from_matrix4(m, warnings)
    } else if let Some(m) = def.matrix3x4 {
        check_finite(index, "matrix3x4", m.as_flattened())?;
        let r = [
            [m[0][0], m[0][1], m[0][2]],
            [m[1][0], m[1][1], m[1][2]],
            [m[2][0], m[2][1], m[2][2]],
        ];
        let d = [m[0][3], m[1][3], m[2][3]];
        if quiet {
            return Transform::from_matrix3_quiet(r, d);
        }
        Transform::from_matrix3(r, d, warnings)
    } else {
        // Unreachable: exactly one form was found above.
        Err(Error::new(
            Code::Parse,
            format!("rig TOML: [[transform]] #{index}: no rotation form"),
        ))
    }
}

/// Resolve an include path: relative, inside the TOML's directory, no `..`.
fn include_path(toml_path: &Path, file: &str, loc: &Location) -> Result<PathBuf> {
    let rel = Path::new(file);
    let bad = file.trim().is_empty()
        || rel.is_absolute()
        || rel
            .components()
            .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir));
    if bad {
        return Err(Error::parse(format!(
            "rig TOML: [[include]] file: expected a relative path beside the rig file (no `..`, not absolute), found \"{file}\""
        ))
        .at(loc));
    }
    let is_toml = rel
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    if is_toml {
        return Err(Error::parse(format!(
            "rig TOML: [[include]] file: expected a raw calibration file (URDF, YAML, JSON, ...), found a TOML file \"{file}\" (rig files do not nest)"
        ))
        .at(loc));
    }
    let dir = toml_path.parent().unwrap_or_else(|| Path::new(""));
    Ok(dir.join(rel))
}

fn load_include(
    inc: &IncludeDef,
    toml_path: &Path,
    includes: Option<&dyn Includes>,
    loc: &Location,
) -> Result<Parsed> {
    let p = include_path(toml_path, &inc.file, loc)?;
    let Some(includes) = includes else {
        return Err(Error::usage(format!(
            "rig TOML: [[include]] file \"{}\": the rig file was parsed on its own; read it with formats::load_file to load what it includes",
            inc.file
        ))
        .at(loc));
    };
    includes
        .include(&p, inc.key.clone(), inc.invert)
        .map_err(|e| {
            let msg = format!(
                "{} (included from {})",
                e.message,
                Location {
                    column: None,
                    ..loc.clone()
                }
            );
            Error { message: msg, ..e }
        })
}

/// The tool's own TOML rig file.
pub const SPEC: FormatSpec = FormatSpec {
    id: "rig-toml",
    description: "the tool's own TOML rig file (see calibrations/README.md)",
    extensions: &["toml"],
    walk: &[".toml"],
    magic: &[],
    sniff: |_| None,
    parse: |i, o| read(i.text()?, i.path(), o, i.includes()),
    checked: true,
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_from_one() {
        let t = "ab\ncd\né f";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 4), (2, 2));
        assert_eq!(line_col(t, 9), (3, 3));
        // Offsets past the end or inside a character do not panic.
        assert_eq!(line_col(t, 1000).0, 3);
        assert_eq!(line_col(t, 7).0, 3);
    }

    /// Whether the subset reader took `t`; when it did, it read what the
    /// toml crate reads (typed file and spans, compared by their Debug text,
    /// which tells -0.0 from 0.0).
    fn same_as_toml(t: &str) -> bool {
        let Some(got) = read_subset(t) else {
            return false;
        };
        match read_toml(t, Path::new("x.toml")) {
            Ok(want) => assert_eq!(format!("{got:?}"), format!("{want:?}"), "{t}"),
            Err(e) => panic!("the subset reader took what the toml crate refuses ({e}):\n{t}"),
        }
        true
    }

    fn shipped_rigs() -> Vec<String> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("calibrations");
        let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        paths.sort();
        paths
            .iter()
            .map(|p| std::fs::read_to_string(p).unwrap())
            .collect()
    }

    #[test]
    fn the_subset_reader_reads_the_shipped_rigs_as_the_toml_crate() {
        let rigs = shipped_rigs();
        let mut taken = 0;
        for t in &rigs {
            let variants = [
                t.clone(),
                t.replace('\n', "\r\n"),
                t.replace(" = ", "\t=\t").replace('\n', " # end\n"),
                t.replace("[\n", "[ # open\n\n").replace("],\n]", "]\n]"),
                t.replace(" 0.", " +0.")
                    .replace("[1, ", "[1e0, ")
                    .replace(", 1]", ", 1E+0]")
                    .replace(", 0", ", -0"),
            ];
            for (k, v) in variants.iter().enumerate() {
                let took = same_as_toml(v);
                assert!(took, "variant {k} not taken:\n{v}");
                taken += usize::from(took);
            }
        }
        // Every shipped rig is in the subset (none has an inline table or a
        // multi-line string), in each variant.
        assert_eq!(taken, rigs.len() * 5);
    }

    #[test]
    fn the_subset_reader_takes_no_edit_the_toml_crate_reads_otherwise() {
        // Single edits of the shipped rigs at pseudo-random places, with the
        // characters TOML turns on: each either left to the toml crate or
        // read exactly as it reads it.
        const EDITS: [&str; 24] = [
            "\"",
            "\\",
            "[",
            "]",
            ",",
            "=",
            "#",
            "\n",
            " ",
            "0",
            ".",
            "e",
            "-",
            "+",
            "_",
            "'",
            "{",
            "t",
            "\r",
            "\u{1}",
            "1",
            "x = 1\n",
            "[rig]\n",
            "[[transform]]\n",
        ];
        let mut edits = crate::formats::test_edits::Edits::new();
        let (mut taken, mut tried) = (0, 0);
        for t in shipped_rigs() {
            for _ in 0..150 {
                let v = edits.edit(&t, &EDITS);
                taken += usize::from(same_as_toml(&v));
                tried += 1;
            }
        }
        // Some edits keep the file in the subset (a digit, a space): those
        // are the ones compared.
        assert!(taken > tried / 10, "{taken} of {tried}");
    }

    #[test]
    fn include_paths_stay_beside_the_rig() {
        let loc = Location::default();
        let base = Path::new("/x/calibrations/rig.toml");
        assert!(include_path(base, "rig.urdf", &loc).is_ok());
        assert!(include_path(base, "../etc/passwd", &loc).is_err());
        assert!(include_path(base, "/etc/passwd", &loc).is_err());
        assert!(include_path(base, "other.toml", &loc).is_err());
        assert!(include_path(base, "", &loc).is_err());
    }
}

/// `[rig] sigma_t_m`, `sigma_r_deg`: finite, `>= 0`, within the CLI's limits.
fn user_sigma(rig: &RigTable, loc: &Location) -> Result<Option<UserSigma>> {
    if rig.sigma_t_m.is_none() && rig.sigma_r_deg.is_none() {
        return Ok(None);
    }
    let (t, r) = (rig.sigma_t_m.unwrap_or(0.0), rig.sigma_r_deg.unwrap_or(0.0));
    for (what, v, max) in [
        ("sigma_t_m", t, MAX_SIGMA_T_M),
        ("sigma_r_deg", r, MAX_SIGMA_R_DEG),
    ] {
        if !(v.is_finite() && (0.0..=max).contains(&v)) {
            return Err(Error::parse(format!(
                "rig TOML: [rig] {what}: expected a number in [0, {max}], found {v}"
            ))
            .at(loc));
        }
    }
    Ok(Some(UserSigma {
        sigma_t_m: t,
        sigma_r_rad: r.to_radians(),
    }))
}

/// Where one `[[transform]]`'s numbers are written (byte spans), read
/// from the parsed document by reference: the same tables and arrays the
/// typed reading takes the numbers from, so that each number has its digits.
#[derive(Debug, Default)]
struct LiteralSpans {
    translation: Option<Vec<Range<usize>>>,
    rotation_matrix: Option<Vec<Range<usize>>>,
    quaternion_xyzw: Option<Vec<Range<usize>>>,
    quaternion_wxyz: Option<Vec<Range<usize>>>,
    rpy: Option<Vec<Range<usize>>>,
    ypr: Option<Vec<Range<usize>>>,
    /// The axis's three, then the angle.
    axis_angle: Option<(Vec<Range<usize>>, Range<usize>)>,
    matrix4: Option<Vec<Range<usize>>>,
    matrix3x4: Option<Vec<Range<usize>>>,
}

/// The spans of every `[[transform]]`'s numbers, in order; `None` when a
/// field the spans are read from is not a number or an array of them (then
/// the typed reading refuses the file too). Rows of a matrix are flattened.
fn literal_spans(doc: &DeTable) -> Option<Vec<LiteralSpans>> {
    let Some(list) = doc.get("transform") else {
        return Some(Vec::new());
    };
    let DeValue::Array(list) = list.get_ref() else {
        return None;
    };
    list.iter()
        .map(|t| match t.get_ref() {
            DeValue::Table(t) => transform_spans(t),
            _ => None,
        })
        .collect()
}

fn transform_spans(t: &DeTable) -> Option<LiteralSpans> {
    fn number(v: &Spanned<DeValue>) -> Option<Range<usize>> {
        matches!(v.get_ref(), DeValue::Integer(_) | DeValue::Float(_)).then(|| v.span())
    }
    // Numbers, or (`depth` 2) arrays of numbers, flattened.
    fn numbers(v: &Spanned<DeValue>, depth: usize, out: &mut Vec<Range<usize>>) -> Option<()> {
        let DeValue::Array(a) = v.get_ref() else {
            return None;
        };
        for x in a.iter() {
            if depth > 1 {
                numbers(x, depth - 1, out)?;
            } else {
                out.push(number(x)?);
            }
        }
        Some(())
    }
    let field = |name: &str, depth: usize| -> Option<Option<Vec<Range<usize>>>> {
        let Some(v) = t.get(name) else {
            return Some(None);
        };
        let mut out = Vec::new();
        numbers(v, depth, &mut out)?;
        Some(Some(out))
    };
    let axis_angle = match t.get("axis_angle").map(|v| v.get_ref()) {
        None => None,
        Some(DeValue::Table(aa)) => {
            let mut axis = Vec::new();
            numbers(aa.get("axis")?, 1, &mut axis)?;
            Some((axis, number(aa.get("angle")?)?))
        }
        Some(_) => return None,
    };
    Some(LiteralSpans {
        translation: field("translation", 1)?,
        rotation_matrix: field("rotation_matrix", 2)?,
        quaternion_xyzw: field("quaternion_xyzw", 1)?,
        quaternion_wxyz: field("quaternion_wxyz", 1)?,
        rpy: field("rpy", 1)?,
        ypr: field("ypr", 1)?,
        axis_angle,
        matrix4: field("matrix4", 2)?,
        matrix3x4: field("matrix3x4", 2)?,
    })
}

impl LiteralSpans {
    /// Where the translation's and the rotation's first numbers are written
    /// (a 4x4 or 3x4 matrix holds both: its first number for each).
    fn values_at(&self, lines: &LineIndex) -> ValuesAt {
        let at = |s: &Range<usize>| lines.pos(s.start);
        let rotation = self
            .rotation_tuples()
            .first()
            .and_then(|t| t.first().map(at));
        let translation = self
            .translation
            .as_ref()
            .and_then(|t| t.first().map(at))
            .or(rotation);
        ValuesAt::new(translation, rotation)
    }

    /// The rotation form's numbers as tuples (one per form; axis-angle two).
    fn rotation_tuples(&self) -> Vec<&[Range<usize>]> {
        if let Some((axis, angle)) = &self.axis_angle {
            return vec![axis, std::slice::from_ref(angle)];
        }
        [
            &self.rotation_matrix,
            &self.quaternion_xyzw,
            &self.quaternion_wxyz,
            &self.rpy,
            &self.ypr,
            &self.matrix4,
            &self.matrix3x4,
        ]
        .into_iter()
        .flatten()
        .map(Vec::as_slice)
        .collect()
    }
}

/// The numbers of `d` replaced by `p`: translation first (when separate),
/// then the rotation form's numbers in the order written. Every number of
/// the forms `d` holds is written, so one copy serves every step of a
/// derivative (copying the whole record per step was a twentieth of
/// checking a rig file, issue 29).
fn set_params(d: &mut Numbers, p: &[f64]) {
    let mut it = p.iter().copied();
    let mut next = || it.next().unwrap_or(0.0);
    if let Some(t) = &mut d.translation {
        t.iter_mut().for_each(|x| *x = next());
    }
    if let Some((axis, angle)) = &mut d.axis_angle {
        axis.iter_mut().for_each(|x| *x = next());
        *angle = next();
    }
    let fields = [
        d.rotation_matrix.as_mut().map(|m| m.as_flattened_mut()),
        d.quaternion_xyzw.as_mut().map(|q| &mut q[..]),
        d.quaternion_wxyz.as_mut().map(|q| &mut q[..]),
        d.rpy.as_mut().map(|q| &mut q[..]),
        d.ypr.as_mut().map(|q| &mut q[..]),
        d.matrix4.as_mut().map(|m| m.as_flattened_mut()),
        d.matrix3x4.as_mut().map(|m| m.as_flattened_mut()),
    ];
    for xs in fields.into_iter().flatten() {
        xs.iter_mut().for_each(|x| *x = next());
    }
}

/// The rounding of one `[[transform]]`'s numbers as written, propagated
/// through the same construction as the edge (unit, inversion); `default`
/// (none recorded) when the spans do not match the numbers.
fn precision_of(index: usize, def: &Numbers, lits: &LiteralSpans, text: &str) -> EdgePrecision {
    let mut spans: Vec<&[Range<usize>]> = Vec::new();
    let mut values: Vec<Vec<f64>> = Vec::new();
    if let Some(t) = def.translation {
        spans.push(lits.translation.as_deref().unwrap_or_default());
        values.push(t.to_vec());
    }
    spans.extend(lits.rotation_tuples());
    values.extend(def.rotation_tuples());
    let matched =
        spans.len() == values.len() && spans.iter().zip(&values).all(|(s, v)| s.len() == v.len());
    if !matched {
        return EdgePrecision::default();
    }
    let (mut params, mut halves) = (Vec::new(), Vec::new());
    for (tuple, numbers) in spans.iter().zip(values) {
        let texts: Vec<&str> = tuple
            .iter()
            .map(|s| text.get(s.clone()).unwrap_or("").trim_start_matches('+'))
            .collect();
        halves.extend(tuple_half_units(&texts));
        params.extend(numbers);
    }
    let scratch = std::cell::RefCell::new(*def);
    let build = |p: &[f64]| {
        let mut d = scratch.borrow_mut();
        set_params(&mut d, p);
        let t = rotation(index, &d, d.translation.unwrap_or([0.0; 3]), None)?;
        let t = match d.unit {
            Unit::M => t,
            Unit::Mm => t.scaled_translation(1e-3),
        };
        Ok(if d.invert { t.inverse() } else { t })
    };
    match rounding_covariance(&params, &halves, build) {
        Ok(c) => EdgePrecision {
            rounding: Some(c),
            user: None,
        },
        Err(_) => EdgePrecision::default(),
    }
}
