//! A small structural checker for the JSON outputs, with the specs transcribed
//! from the README's "JSON" section (rig report, survey JSON, degeneracy
//! report) and the report types in `src/report/`. A spec is JSON: a type string ("string", "number", "integer",
//! "boolean", "null", unions "number|null", enums "enum:a|b|c"), an object of
//! field specs (every field required), or `{"array": SPEC, "len": N}` /
//! `{"array": SPEC}`; `{"nullable": SPEC}` allows null.

use serde_json::{json, Value};

pub fn check(v: &Value, spec: &Value, path: &str) -> Vec<String> {
    let mut errs = Vec::new();
    walk(v, spec, path, &mut errs);
    errs
}

fn type_ok(v: &Value, t: &str) -> bool {
    if let Some(list) = t.strip_prefix("enum:") {
        return v.as_str().is_some_and(|s| list.split('|').any(|x| x == s));
    }
    t.split('|').any(|t| match t {
        "string" => v.is_string(),
        "number" => v.is_number(),
        "integer" => v.is_u64() || v.is_i64(),
        "boolean" => v.is_boolean(),
        "null" => v.is_null(),
        _ => panic!("bad spec type {t}"),
    })
}

fn walk(v: &Value, spec: &Value, path: &str, errs: &mut Vec<String>) {
    match spec {
        Value::String(t) => {
            if !type_ok(v, t) {
                errs.push(format!("{path}: expected {t}, found {v}"));
            }
        }
        Value::Object(m) if m.contains_key("nullable") => {
            if !v.is_null() {
                walk(v, &m["nullable"], path, errs);
            }
        }
        Value::Object(m) if m.contains_key("array") => {
            let Some(a) = v.as_array() else {
                errs.push(format!("{path}: expected array, found {v}"));
                return;
            };
            if let Some(n) = m.get("len").and_then(Value::as_u64) {
                if a.len() as u64 != n {
                    errs.push(format!("{path}: expected {n} elements, found {}", a.len()));
                }
            }
            for (i, x) in a.iter().enumerate() {
                walk(x, &m["array"], &format!("{path}[{i}]"), errs);
            }
        }
        Value::Object(fields) => {
            let Some(o) = v.as_object() else {
                errs.push(format!("{path}: expected object, found {v}"));
                return;
            };
            for (k, s) in fields {
                match o.get(k) {
                    Some(x) => walk(x, s, &format!("{path}.{k}"), errs),
                    None => errs.push(format!("{path}: missing field `{k}`")),
                }
            }
        }
        _ => panic!("bad spec {spec}"),
    }
}

fn arr(spec: Value, n: u64) -> Value {
    json!({"array": spec, "len": n})
}

/// README "JSON": the rig report (`src/report/rig.rs`).
pub fn rig_report_spec() -> Value {
    json!({
        "schema_version": "integer",
        "from": "string",
        "to": "string",
        "sources": {"array": {"file": "string", "line": "integer|null", "format": "string"}},
        "transform": {
            "translation_m": arr(json!("number"), 3),
            "rotation_matrix": arr(arr(json!("number"), 3), 3),
            "quaternion_xyzw": arr(json!("number"), 4),
            "rpy_rad": arr(json!("number"), 3)
        },
        "lever_arm_m": "number",
        "rotation": {"angle_rad": "number", "angle_deg": "number",
                     "axis": {"nullable": arr(json!("number"), 3)}},
        "screw": {
            "kind": "enum:identity|pure_translation|zero_pitch|general",
            "translation_along_axis_m": "number|null",
            "pitch_m_per_rad": "number|null",
            "axis_point_m": {"nullable": arr(json!("number"), 3)}
        },
        "adjoint": {"singular_values": arr(json!("number"), 6), "orthogonal": "boolean",
                    "ata_minus_i_rel": "number"},
        "certificate": {"array": {"ell_m": "number", "delta_eff": "number",
                                  "band": arr(json!("number"), 2)}},
        "adapted_metric": {
            "exists": "boolean", "reason": "string",
            "matrix": {"nullable": arr(arr(json!("number"), 6), 6)},
            "invariance_residual": "number|null", "offdiag_norm": "number|null",
            "rel_diff_identity": "number|null"
        },
        "detectors": {"array": {
            "family": "enum:unnormalized|characteristic_length|block_scaling|jacobi|adapted_constant|point_displacement",
            "equivariant_rule": "boolean", "invariant_on_rig": "boolean", "reason": "string"
        }}
    })
}

/// README "JSON": the survey JSON (`src/report/survey.rs`).
pub fn survey_spec() -> Value {
    json!({
        "schema_version": "integer",
        "rigs": {"array": {
            "id": "string", "sensor": "string", "platform": "string", "dataset": "string",
            "from": "string", "to": "string", "lever_arm_m": "number", "angle_deg": "number",
            "screw_translation_m": "number|null", "zero_pitch": "boolean",
            "sigma_max": "number", "band_l1": arr(json!("number"), 2),
            "adapted_metric_exists": "boolean"
        }},
        "summary": {"count": "integer", "lever_arm_min_m": "number",
                    "lever_arm_median_m": "number", "lever_arm_max_m": "number",
                    "nonzero_pitch_count": "integer"}
    })
}

/// README "JSON": the degeneracy report (`src/report/detector.rs`).
pub fn degeneracy_spec() -> Value {
    json!({
        "schema_version": "integer",
        "points": "integer",
        "frame": {"translation_m": arr(json!("number"), 3), "rpy_rad": arr(json!("number"), 3)},
        "families": {"array": {"family": "string", "eigenvalues": arr(json!("number"), 6),
                               "threshold": "number", "degenerate_count": "integer"}},
        "degenerate_subspace": {"array": {
            "eigenvalue": "number", "twist": arr(json!("number"), 6),
            "screw": {"kind": "string", "axis": {"nullable": arr(json!("number"), 3)},
                      "pitch_m_per_rad": "number|null",
                      "axis_point_m": {"nullable": arr(json!("number"), 3)},
                      "direction": {"nullable": arr(json!("number"), 3)}}
        }},
        "footprint": {"array": "boolean", "len": 6}
    })
}
