//! `audit FILE... --from A --to B`: the rig report.

use super::{parse_joint, parse_nonneg, parse_positive, print_warnings, Style};
use crate::diagnostic::{Error, Result};
use crate::formats::{self, LoadOptions};
use crate::frames::{Chain, FrameGraph};
use crate::report::{self, fixed, short, vec_str, RigReport};
use crate::tolerances::DEFAULT_MAX_FILE_SIZE;
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum ReportFormat {
    #[default]
    Table,
    Markdown,
    Json,
}

#[derive(Debug, Args, Clone)]
pub struct AuditArgs {
    /// Files to load into one frame graph (URDF, launch, tf_static dump, YAML, JSON, TOML rig)
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Parent frame: the transform printed is the pose of --to in --from
    #[arg(long, value_name = "FRAME")]
    pub from: Option<String>,
    /// Child frame (e.g. the LiDAR)
    #[arg(long, value_name = "FRAME")]
    pub to: Option<String>,
    /// List the frames and edges the files yield (with file:line), then exit
    #[arg(long)]
    pub frames: bool,
    /// Characteristic lengths (m) for the certificate bands
    #[arg(long, value_delimiter = ',', default_value = "0.25,1,2.85,10", value_parser = parse_positive, value_name = "M,...")]
    pub ell: Vec<f64>,
    /// Detector threshold kappa: with --lambda, does the band certify that lambda cannot cross kappa?
    #[arg(long, requires = "lambda", value_parser = parse_positive)]
    pub kappa: Option<f64>,
    /// Detector eigenvalue lambda (see --kappa)
    #[arg(long, requires = "kappa", value_parser = parse_nonneg)]
    pub lambda: Option<f64>,
    /// Zero-pitch tolerance on |h| (m); the raw h is always printed beside the verdict
    #[arg(long, default_value_t = crate::tolerances::DEFAULT_PITCH_TOL, value_parser = parse_nonneg, value_name = "M")]
    pub pitch_tol: f64,
    /// Set a movable joint's position (rad or m); repeatable
    #[arg(long = "joint", value_parser = parse_joint, value_name = "NAME=VALUE")]
    pub joints: Vec<(String, f64)>,
    /// Rename a frame as it is loaded, in every file or only in FILE (e.g.
    /// `fast_lio.yaml:imu=imu_link` to attach a FAST-LIO extrinsic to a URDF); repeatable
    #[arg(long = "rename", value_parser = parse_rename, value_name = "[FILE:]OLD=NEW")]
    pub renames: Vec<Rename>,
    /// Read only this key of a YAML/JSON file (e.g. T_imu_lidar)
    #[arg(long, value_name = "NAME")]
    pub key: Option<String>,
    /// The file stores the other direction: invert its transforms
    #[arg(long)]
    pub invert: bool,
    /// Skip format detection (see the README's formats table)
    #[arg(long, value_name = "NAME")]
    pub input_format: Option<String>,
    /// Refuse input files larger than this many bytes
    #[arg(long, default_value_t = DEFAULT_MAX_FILE_SIZE, value_name = "BYTES")]
    pub max_file_size: u64,
    /// Output format
    #[arg(long, value_enum, default_value_t = ReportFormat::Table)]
    pub format: ReportFormat,
    /// xacro `$(arg NAME)` value, overriding the file's xacro:arg default; repeatable
    #[arg(long = "arg", value_parser = parse_xacro_arg, value_name = "NAME=VALUE")]
    pub xacro_args: Vec<(String, String)>,
    /// Where xacro `$(find pkg)` looks first: a package directory or a directory
    /// holding packages; repeatable
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_paths: Vec<PathBuf>,
    /// How .xacro files are expanded: `native` (built in) or `external` (the
    /// `xacro` program on PATH)
    #[arg(long = "xacro", value_enum, default_value_t = XacroMode::Native)]
    pub xacro_mode: XacroMode,
}

/// `--xacro native|external`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum XacroMode {
    Native,
    External,
}

/// `--arg NAME=VALUE` (the value is text, as `xacro NAME:=VALUE` takes it).
fn parse_xacro_arg(s: &str) -> std::result::Result<(String, String), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE, found `{s}`"))?;
    let name = name.trim().trim_end_matches(':');
    if name.is_empty() {
        return Err(format!("expected NAME=VALUE, found `{s}`"));
    }
    Ok((name.to_string(), value.to_string()))
}

impl AuditArgs {
    pub fn load_options(&self) -> Result<LoadOptions> {
        let format = match &self.input_format {
            None => None,
            Some(name) => Some(formats::Format::from_name(name)?),
        };
        Ok(LoadOptions {
            joints: self.joints.iter().cloned().collect(),
            key: self.key.clone(),
            invert: self.invert,
            format,
            max_file_size: self.max_file_size,
            xacro_args: self.xacro_args.iter().cloned().collect(),
            package_paths: self.package_paths.clone(),
            xacro_external: self.xacro_mode == XacroMode::External,
            ..LoadOptions::default()
        })
    }
}

/// `--rename [FILE:]OLD=NEW`.
#[derive(Debug, Clone, PartialEq)]
pub struct Rename {
    /// Only in files whose path ends with this (`None`: every file).
    pub file: Option<String>,
    pub old: String,
    pub new: String,
}

pub fn parse_rename(s: &str) -> std::result::Result<Rename, String> {
    let (lhs, new) = s
        .rsplit_once('=')
        .ok_or_else(|| format!("expected [FILE:]OLD=NEW, found `{s}`"))?;
    let (file, old) = match lhs.rsplit_once(':') {
        Some((f, o)) => (Some(f.to_string()), o),
        None => (None, lhs),
    };
    if old.is_empty() || new.is_empty() || file.as_deref() == Some("") {
        return Err(format!(
            "expected [FILE:]OLD=NEW with non-empty names, found `{s}`"
        ));
    }
    Ok(Rename {
        file,
        old: old.to_string(),
        new: new.to_string(),
    })
}

/// Apply the renames that concern `path` to what it yielded; returns how many
/// frame names changed.
fn apply_renames(
    renames: &[Rename],
    path: &std::path::Path,
    loaded: &mut formats::Loaded,
) -> usize {
    let p = path.to_string_lossy();
    let mut n = 0;
    for r in renames {
        if r.file.as_deref().is_some_and(|f| !p.ends_with(f)) {
            continue;
        }
        for e in &mut loaded.edges {
            for name in [&mut e.parent, &mut e.child] {
                if *name == r.old {
                    *name = r.new.clone();
                    n += 1;
                }
            }
        }
        if let Some(meta) = &mut loaded.rig {
            for name in [&mut meta.from, &mut meta.to] {
                if *name == r.old {
                    *name = r.new.clone();
                }
            }
        }
    }
    n
}

/// Pick the frame pair: given on the command line, declared by a rig file, or
/// the only edge there is.
fn frame_pair(
    args: &AuditArgs,
    graph: &FrameGraph,
    rig: Option<(&str, &str)>,
) -> Result<(String, String)> {
    match (&args.from, &args.to) {
        (Some(f), Some(t)) => Ok((f.clone(), t.clone())),
        (None, None) => {
            if let Some((f, t)) = rig {
                return Ok((f.to_string(), t.to_string()));
            }
            let edges = graph.edges();
            if edges.len() == 1 {
                return Ok((edges[0].parent.clone(), edges[0].child.clone()));
            }
            Err(Error::usage(format!(
                "these files yield {} edges: name the frames with --from FRAME --to FRAME (frames: {}; `--frames` lists them)",
                edges.len(),
                abbreviate(&graph.frames(), 12)
            )))
        }
        _ => Err(Error::usage(
            "give both --from and --to, or neither (when the files yield one edge)",
        )),
    }
}

fn abbreviate(v: &[String], n: usize) -> String {
    if v.len() <= n {
        v.join(", ")
    } else {
        format!("{}, ... ({} in all)", v[..n].join(", "), v.len())
    }
}

pub fn run(args: &AuditArgs, out: &mut dyn Write) -> Result<i32> {
    let opts = args.load_options()?;
    let mut graph = FrameGraph::new();
    let mut rig_pair: Option<(String, String)> = None;
    let mut renamed = vec![0usize; args.renames.len()];
    for f in &args.files {
        let mut loaded = formats::load_file(f, &opts)?;
        for (i, r) in args.renames.iter().enumerate() {
            renamed[i] += apply_renames(std::slice::from_ref(r), f, &mut loaded);
        }
        if let Some(meta) = &loaded.rig {
            if rig_pair.is_none() && !meta.from.is_empty() && !meta.to.is_empty() {
                rig_pair = Some((meta.from.clone(), meta.to.clone()));
            }
        }
        graph.add(loaded)?;
    }
    if let Some(i) = renamed.iter().position(|&n| n == 0) {
        let r = &args.renames[i];
        return Err(Error::usage(format!(
            "--rename {}{}={}: expected a frame `{}` in {}, found none",
            r.file
                .as_deref()
                .map(|f| format!("{f}:"))
                .unwrap_or_default(),
            r.old,
            r.new,
            r.old,
            r.file.as_deref().unwrap_or("the files")
        )));
    }
    print_warnings(graph.warnings());
    check_joint_names(args, &graph)?;
    if args.frames {
        writeln!(out, "{}", graph.tree()).map_err(io_err)?;
        return Ok(0);
    }
    let (from, to) = frame_pair(
        args,
        &graph,
        rig_pair.as_ref().map(|(a, b)| (a.as_str(), b.as_str())),
    )?;
    let chain = graph.transform(&from, &to)?;
    print_warnings(&chain.warnings);
    let mut rep = report::rig_report(&chain, &args.ell, args.pitch_tol)?;
    if let (Some(kappa), Some(lambda)) = (args.kappa, args.lambda) {
        rep.kappa_check = Some(report::kappa_check(&rep, kappa, lambda)?);
    }
    let text = match args.format {
        ReportFormat::Json => {
            let mut s =
                serde_json::to_string_pretty(&rep).map_err(|e| Error::usage(e.to_string()))?;
            s.push('\n');
            s
        }
        ReportFormat::Table => render(&rep, &chain, Style::stdout(), false),
        ReportFormat::Markdown => render(&rep, &chain, Style::plain(), true),
    };
    out.write_all(text.as_bytes()).map_err(io_err)?;
    Ok(0)
}

/// A `--joint` that names no joint is a typo, not a no-op.
fn check_joint_names(args: &AuditArgs, graph: &FrameGraph) -> Result<()> {
    let known = graph.joint_names();
    for (name, _) in &args.joints {
        if !known.contains(name) {
            let mut close: Vec<&String> = known
                .iter()
                .filter(|k| strsim::normalized_levenshtein(k, name) > 0.5)
                .collect();
            close.truncate(3);
            let hint = if close.is_empty() {
                format!(
                    "movable joints in these files: {}",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        abbreviate(&known, 12)
                    }
                )
            } else {
                format!(
                    "did you mean {}?",
                    close
                        .iter()
                        .map(|c| format!("`{c}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            };
            return Err(Error::usage(format!(
                "--joint {name}=...: expected the name of a movable joint, found no joint `{name}`; {hint}"
            )));
        }
    }
    Ok(())
}

pub(crate) fn io_err(e: std::io::Error) -> Error {
    Error::new(
        crate::diagnostic::ErrorKind::Io,
        format!("cannot write output: {e}"),
    )
}

/// The one-line verdict that opens the report.
pub fn verdict_line(rep: &RigReport) -> String {
    let invariant: Vec<&str> = rep
        .detectors
        .iter()
        .filter(|d| d.invariant_on_rig)
        .map(|d| family_label(&d.family))
        .collect();
    let lever = format!("lever arm {} m", fixed(rep.lever_arm_m, 3));
    let screw = match rep.screw.kind.as_str() {
        "identity" => "identity transform".to_string(),
        "pure_translation" => "no rotation (pure translation)".to_string(),
        _ => {
            let deg = rep.rotation.angle_deg;
            let caveat = if deg < crate::tolerances::SMALL_ROTATION_DEG {
                format!(
                    " (rotation only {} deg: the screw axis is set by calibration noise)",
                    fixed(deg, 3)
                )
            } else if (180.0 - deg).to_radians() < crate::tolerances::NEAR_HALF_TURN_RAD {
                " (half-turn: the sign of h follows the rounding)".to_string()
            } else {
                String::new()
            };
            format!(
                "screw translation {} m{caveat}",
                short(rep.screw.translation_along_axis_m.unwrap_or(0.0))
            )
        }
    };
    let tail = if invariant.len() == rep.detectors.len() && !invariant.is_empty() {
        "every detector family is frame-invariant on this rig".to_string()
    } else if invariant.len() == 1 && invariant[0] == family_label("point_displacement") {
        if rep.adapted_metric.exists {
            "only the point-displacement metric is frame-invariant on this rig".to_string()
        } else {
            "no constant metric is frame-invariant on this rig; only the point-displacement metric is".to_string()
        }
    } else if invariant.is_empty() {
        "no detector family is frame-invariant on this rig".to_string()
    } else {
        format!("frame-invariant on this rig: {}", invariant.join(", "))
    };
    format!("{lever}, {screw}: {tail}")
}

pub fn family_label(name: &str) -> &'static str {
    match name {
        "unnormalized" => "unnormalized spectrum (I6)",
        "characteristic_length" => "characteristic length diag(l^2 I, I)",
        "block_scaling" => "block scaling (l from H)",
        "jacobi" => "Jacobi diag(H)",
        "adapted_constant" => "adapted constant M0",
        "point_displacement" => "point displacement sum J^T J",
        _ => "unknown",
    }
}

fn section(s: &mut String, title: &str, st: Style, md: bool) {
    if md {
        s.push_str(&format!("\n### {title}\n\n"));
    } else {
        s.push_str(&format!("\n{}\n", st.bold(title)));
    }
}

fn table(header: &[&str], rows: &[Vec<String>], md: bool) -> String {
    if md {
        report::markdown_table(header, rows)
    } else {
        let mut t = report::terminal_table(header, rows);
        t.push('\n');
        t
    }
}

/// Table and markdown renderings of the rig report.
pub fn render(rep: &RigReport, chain: &Chain, st: Style, md: bool) -> String {
    let mut s = String::new();
    let verdict = verdict_line(rep);
    if md {
        s.push_str(&format!("**{verdict}**\n"));
    } else if rep.detectors.iter().filter(|d| d.invariant_on_rig).count() > 1 {
        s.push_str(&format!("{}\n", st.good(&verdict)));
    } else {
        s.push_str(&format!("{}\n", st.bad(&verdict)));
    }

    section(
        &mut s,
        &format!("Transform {} -> {}", rep.from, rep.to),
        st,
        md,
    );
    let tf = &rep.transform;
    let (angle_deg, axis) = (rep.rotation.angle_deg, rep.rotation.axis);
    let rows = vec![
        vec!["translation (m)".into(), vec_str(&tf.translation_m, 9)],
        vec![
            "rotation matrix row 1".into(),
            vec_str(&tf.rotation_matrix[0], 9),
        ],
        vec![
            "rotation matrix row 2".into(),
            vec_str(&tf.rotation_matrix[1], 9),
        ],
        vec![
            "rotation matrix row 3".into(),
            vec_str(&tf.rotation_matrix[2], 9),
        ],
        vec![
            "quaternion [x, y, z, w]".into(),
            vec_str(&tf.quaternion_xyzw, 9),
        ],
        vec![
            "URDF rpy (rad)".into(),
            format!(
                "{}  = {} deg",
                vec_str(&tf.rpy_rad, 9),
                vec_str(&tf.rpy_rad.map(f64::to_degrees), 6)
            ),
        ],
        vec![
            "axis-angle".into(),
            match axis {
                Some(e) => format!("{} deg about {}", fixed(angle_deg, 6), vec_str(&e, 6)),
                None => format!("{} deg (no axis)", fixed(angle_deg, 6)),
            },
        ],
    ];
    if !md {
        s.push_str(&format!(
            "{}\n",
            st.dim(&format!(
                "pose of {} in {}: p_{} = R p_{} + d",
                rep.to, rep.from, rep.from, rep.to
            ))
        ));
    } else {
        s.push_str(&format!(
            "Pose of `{}` in `{}`: `p_{} = R p_{} + d`.\n\n",
            rep.to, rep.from, rep.from, rep.to
        ));
    }
    s.push_str(&table(&["quantity", "value"], &rows, md));

    section(&mut s, "Chain of edges", st, md);
    let rows: Vec<Vec<String>> = chain
        .steps
        .iter()
        .enumerate()
        .map(|(i, step)| {
            let e = &step.edge;
            let (a, b) = if step.inverted {
                (e.child.as_str(), e.parent.as_str())
            } else {
                (e.parent.as_str(), e.child.as_str())
            };
            vec![
                format!("{}", i + 1),
                format!(
                    "{a} -> {b}{}",
                    if step.inverted { " (inverted)" } else { "" }
                ),
                e.provenance.location.to_string(),
                e.provenance.format.to_string(),
                e.provenance.key.clone(),
            ]
        })
        .collect();
    if rows.is_empty() {
        s.push_str("(from and to are the same frame)\n");
    } else {
        s.push_str(&table(
            &["#", "edge", "file:line", "format", "from"],
            &rows,
            md,
        ));
    }

    section(&mut s, "Rig", st, md);
    let sc = &rep.screw;
    let mut rows = vec![
        vec![
            "lever arm ||d||".into(),
            format!("{} m", fixed(rep.lever_arm_m, 6)),
        ],
        vec![
            "rotation angle".into(),
            format!(
                "{} deg ({} rad)",
                fixed(angle_deg, 6),
                short(rep.rotation.angle_rad)
            ),
        ],
        vec!["screw kind".into(), sc.kind.replace('_', " ")],
    ];
    if let Some(h) = sc.translation_along_axis_m {
        rows.push(vec![
            "screw translation h = e.d".into(),
            format!("{} m", report::short(h)),
        ]);
    }
    if let Some(p) = sc.pitch_m_per_rad {
        rows.push(vec![
            "screw pitch h/phi".into(),
            format!("{} m/rad", short(p)),
        ]);
    }
    if let Some(c) = sc.axis_point_m {
        rows.push(vec![
            "screw axis point (closest to origin)".into(),
            format!("{} m", vec_str(&c, 6)),
        ]);
    }
    let sv = rep.adjoint.singular_values;
    rows.push(vec![
        "Ad(T) singular values".into(),
        format!("{} (x2), 1 (x2), {} (x2)", fixed(sv[0], 6), fixed(sv[5], 6)),
    ]);
    rows.push(vec![
        "Ad(T) orthogonal".into(),
        if rep.adjoint.orthogonal {
            "yes (d = 0)".into()
        } else {
            "no (d != 0)".into()
        },
    ]);
    rows.push(vec![
        "||A^T A - I||_F / ||I||_F".into(),
        fixed(rep.adjoint.ata_minus_i_rel, 6),
    ]);
    s.push_str(&table(&["quantity", "value"], &rows, md));

    section(&mut s, "Certificate bands", st, md);
    let rows: Vec<Vec<String>> = rep
        .certificate
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let mut r = vec![
                short(c.ell_m),
                fixed(c.delta_eff, 6),
                fixed(c.band[0], 6),
                fixed(c.band[1], 6),
            ];
            if let Some(k) = &rep.kappa_check {
                r.push(if k.certified[i] {
                    "yes".into()
                } else {
                    "no".into()
                });
            }
            r
        })
        .collect();
    let mut header = vec!["ell (m)", "delta_eff", "band lower", "band upper"];
    if rep.kappa_check.is_some() {
        header.push("lambda/kappa outside: certified");
    }
    s.push_str(&table(&header, &rows, md));
    s.push_str(
        "If lambda/kappa lies outside the band, no frame change with this lever arm can move eigenvalue lambda across threshold kappa.\n",
    );
    if let Some(k) = &rep.kappa_check {
        s.push_str(&format!(
            "lambda/kappa = {} / {} = {}\n",
            short(k.lambda),
            short(k.kappa),
            short(k.ratio)
        ));
    }

    section(&mut s, "Adapted constant metric", st, md);
    let am = &rep.adapted_metric;
    if am.exists {
        s.push_str(&format!("exists: {}\n", am.reason));
        if let Some(m) = &am.matrix {
            let rows: Vec<Vec<String>> = m
                .iter()
                .map(|r| r.iter().map(|x| fixed(*x, 6)).collect())
                .collect();
            s.push_str(&table(&["wx", "wy", "wz", "tx", "ty", "tz"], &rows, md));
        }
        let opt = |x: Option<f64>| x.map(short).unwrap_or_else(|| "-".into());
        s.push_str(&format!(
            "invariance residual {}, off-diagonal block norm {}, ||M0 - I||_F/||I||_F {}\n",
            opt(am.invariance_residual),
            opt(am.offdiag_norm),
            opt(am.rel_diff_identity)
        ));
    } else {
        s.push_str(&format!("none: {}\n", am.reason));
    }

    section(&mut s, "Detector families", st, md);
    let rows: Vec<Vec<String>> = rep
        .detectors
        .iter()
        .map(|d| {
            vec![
                family_label(&d.family).to_string(),
                yes_no(d.equivariant_rule),
                yes_no(d.invariant_on_rig),
                d.reason.clone(),
            ]
        })
        .collect();
    let header = ["family", "equivariant rule", "invariant on this rig", "why"];
    if md {
        s.push_str(&report::markdown_table(&header, &rows));
    } else {
        // The reasons are sentences: wrap them.
        s.push_str(&report::terminal_table_wrapped(
            &header,
            &rows,
            &[(0, 22), (3, 60)],
        ));
        s.push('\n');
    }
    s
}

fn yes_no(b: bool) -> String {
    if b { "yes" } else { "no" }.to_string()
}
