//! `audit run`: degeneracy over a recorded run. Arguments here, made into
//! `extrinsic_audit::RunOptions`; the face's `Run` reads the run and each
//! result goes to its files (or standard output) as the scans finish, then
//! the summary is emitted.

use super::args::{parse_positive, BagArgs, EllArgs, OutputArgs, TauArgs, XacroArgs};
use super::display::TermBars;
use super::{emit_warned, print_warnings};
use extrinsic_audit::internals::api::{run_transforms, scan_record};
use extrinsic_audit::internals::pipeline::detector::parse_triple;
use extrinsic_audit::internals::pipeline::files::AtomicFile;
use extrinsic_audit::internals::pipeline::{check_output_target, write_atomic};
use extrinsic_audit::internals::render;
use extrinsic_audit::internals::render::mcap::{RunMcap, RUN_TOPIC};
use extrinsic_audit::internals::report::run_scene::RunTransforms;
use extrinsic_audit::internals::tolerances::{
    PAIR_GATE_M, RAW_MIN_NEIGHBOURS, RAW_NORMAL_RADIUS_M, RAW_VOXEL_RANGE_M, RUN_VOXEL_M,
};
use extrinsic_audit::{Code, Error, OutputFormat, Result, Warning};
use extrinsic_audit::{PoseFormat, Run, RunOptions, RunPairs, RunReport, ScanBound, ScanResult};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Degeneracy over a recorded run: every scan of a bag, a KITTI sequence or a folder of point files, every family, in the robot's frames",
    long_about = "Reads every sensor_msgs/PointCloud2 of a topic of a bag (MCAP, rosbag2 .db3 or folder, ROS 1 \
.bag; through the container's index, streamed), every scan of a KITTI sequence (velodyne/*.bin, times.txt) \
or every point file of a folder (PCD, PLY, CSV, LAS, LAZ; name order), and runs the detector on each: \
the scan's normal fields as stored, or else a voxel grid (--voxel, default 0.1 m) and PCA normals; H and M; \
every family's eigenvalues, count and footprint, in the scan frame (header.frame_id) and in the body \
frames the run's transforms name (/tf_static, /robot_description, --extrinsics files: --frame NAME, \
--all-frames; default the root of the scan frame's tree) or that rig files give (--rig-frames).\n\n\
With --pairs, each scan is paired with the one --pair-step before it at their relative pose \
(the source scan's points, the target's normals, as `audit degeneracy --target`); poses from the \
bag (/tf, which wins, or its only nav_msgs/Odometry topic; --poses-topic) or a file (--poses, \
--poses-format tum | kitti (camera poses, with --calib) | kitti-lidar | named | relative).\n\n\
Output: the summary (scans read and skipped with reasons, degenerate intervals per family, where a \
body frame changes a label, the point-displacement eigenvalues' largest change between frames) as \
text, markdown or JSON; one record per scan or pair as CSV (--csv FILE, or --format csv on \
standard output) and JSON lines (--jsonl FILE); the timeline as SVG (--timeline FILE, or --format \
svg) or as an MCAP file for Foxglove (--format mcap --output FILE.mcap: one message per scan, the \
run's transforms; docs/foxglove.md). Skipped scans are named warnings; the scans before damage (a truncated bag) are reported.\n\n\
Exit codes: 0 the run was read (skipped scans and damage are warnings); 1 with --strict when a scan or \
pair was skipped or damage stopped the read (every output still written); 2 usage error, unreadable \
run or refused output.\n\n\
Examples:\n  audit run run.mcap\n  audit run run.bag --topic /points --frame base_link --csv scans.csv --timeline run.svg\n  \
audit run run_db3/ --pairs --all-frames --format json\n  \
audit run sequences/00 --poses poses/00.txt --poses-format kitti --calib sequences/00/calib.txt --pairs\n  \
audit run 'scans/*.pcd' --every 10 --rig-frames calibrations/ --lidar-frame lidar"
)]
pub struct RunArgs {
    /// The run: a bag (or the parts of one recording), a KITTI sequence folder, a folder of point files, point files or a quoted pattern (`'scans/*.pcd'`).
    #[arg(required = true, num_args = 1..)]
    pub run: Vec<PathBuf>,
    /// The PointCloud2 topic (default: the bag's only one).
    #[arg(long, value_name = "TOPIC")]
    pub topic: Option<String>,
    /// The first scan kept: an index (`120`) or seconds after the first scan (`12.5s`).
    #[arg(long, value_name = "N|Ts")]
    pub start: Option<String>,
    /// The first scan no longer kept: an index or seconds (`60s`).
    #[arg(long, value_name = "N|Ts")]
    pub end: Option<String>,
    /// Keep every N-th scan.
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub every: usize,
    /// Scan pairs at the known relative pose instead of single scans.
    #[arg(long)]
    pub pairs: bool,
    /// With --pairs: pair each scan with the K-th before it.
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub pair_step: usize,
    /// A poses file (one pose per scan or per time; see --poses-format).
    #[arg(long, value_name = "FILE")]
    pub poses: Option<PathBuf>,
    /// What --poses holds: tum, kitti (camera poses, needs --calib), kitti-lidar, named (a name, then 12 numbers) or relative (4x4, scan k+1 in scan k).
    #[arg(long, value_name = "FORMAT", value_parser = parse_pose_format)]
    pub poses_format: Option<PoseFormat>,
    /// KITTI calib.txt (its `Tr`) for --poses-format kitti.
    #[arg(long, value_name = "FILE")]
    pub calib: Option<PathBuf>,
    /// A bag topic with the poses (/tf or a nav_msgs/Odometry topic).
    #[arg(long, value_name = "TOPIC")]
    pub poses_topic: Option<String>,
    /// The frame the poses are of (default: the scan frame; for /tf the root of the scan frame's tree).
    #[arg(long, value_name = "NAME")]
    pub poses_frame: Option<String>,
    /// The scan frame of files that name none (KITTI, point files).
    #[arg(long, value_name = "NAME")]
    pub lidar_frame: Option<String>,
    /// A body frame of the run's transforms to report in; repeatable.
    #[arg(long = "frame", value_name = "NAME")]
    pub frames: Vec<String>,
    /// Every frame of the run's transforms.
    #[arg(long)]
    pub all_frames: bool,
    /// Calibration files (URDF, TF, LIO YAML, ...) whose transforms join the run's.
    #[arg(long, num_args = 1.., value_name = "FILE")]
    pub extrinsics: Vec<PathBuf>,
    /// Rig files (or folders): each gives its body frame (the scan taken as its LiDAR's) and its lever arm alone.
    #[arg(long, num_args = 1.., value_name = "PATH")]
    pub rig_frames: Vec<PathBuf>,
    /// Estimate normals even where the scans have normal fields.
    #[arg(long)]
    pub estimate_normals: bool,
    /// Voxel grid edge (m) before normals are estimated; 0: none.
    #[arg(long, default_value_t = RUN_VOXEL_M, value_parser = parse_run_voxel, value_name = "M")]
    pub voxel: f64,
    /// Neighbourhood radius (m) of the normal estimation.
    #[arg(long, default_value_t = RAW_NORMAL_RADIUS_M, value_parser = parse_positive, value_name = "M")]
    pub normal_radius: f64,
    /// Fewest neighbours (the point counted) for a normal.
    #[arg(long, default_value_t = RAW_MIN_NEIGHBOURS, value_name = "N")]
    pub min_neighbours: usize,
    /// At most the K nearest neighbours within the radius.
    #[arg(long, value_name = "K")]
    pub knn: Option<usize>,
    /// Normals point toward this point `x,y,z` (m, scan frame; default the sensor origin).
    #[arg(long, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub viewpoint: Option<String>,
    /// With --pairs: correspondence gate (m).
    #[arg(long, default_value_t = PAIR_GATE_M, value_parser = parse_positive, value_name = "M")]
    pub gate: f64,
    #[command(flatten)]
    pub tau: TauArgs,
    #[command(flatten)]
    pub ell: EllArgs,
    /// Worker threads (0: AUDIT_JOBS when set, else one per core, as check and survey)
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub threads: usize,
    /// Write one CSV row per scan (or pair) to FILE (.csv).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write one JSON line per scan (or pair) to FILE (.jsonl).
    #[arg(long, value_name = "FILE")]
    pub jsonl: Option<PathBuf>,
    /// Draw the timeline to FILE (.svg).
    #[arg(long, value_name = "FILE")]
    pub timeline: Option<PathBuf>,
    /// Exit 1 when data was lost: a scan or pair skipped (scan-skipped) or the read stopped at damage (run-damaged); the outputs are written all the same
    #[arg(long)]
    pub strict: bool,
    #[command(flatten)]
    pub bag: BagArgs,
    #[command(flatten)]
    pub xacro: XacroArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

fn parse_pose_format(s: &str) -> std::result::Result<PoseFormat, String> {
    PoseFormat::parse(s).map_err(|e| e.message)
}

/// `--voxel`: 0 (none) or within [`RAW_VOXEL_RANGE_M`].
fn parse_run_voxel(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a number of metres, found `{s}`"))?;
    let (lo, hi) = RAW_VOXEL_RANGE_M;
    if v == 0.0 || (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("expected 0 (none) or {lo} to {hi} m, found `{s}`"))
    }
}

impl RunArgs {
    fn options(&self) -> Result<RunOptions> {
        if self.every == 0 {
            return Err(Error::usage("--every: expected at least 1"));
        }
        if !self.pairs && (self.poses.is_some() || self.poses_topic.is_some()) {
            return Err(Error::usage("--poses and --poses-topic apply with --pairs"));
        }
        let bound = |v: &Option<String>, flag| v.as_deref().map(|s| ScanBound::parse(s, flag));
        let mut o = RunOptions::default();
        o.scans.topic = self.topic.clone();
        o.scans.window.start = bound(&self.start, "--start").transpose()?;
        o.scans.window.end = bound(&self.end, "--end").transpose()?;
        o.scans.window.every = self.every;
        o.scans.lidar_frame = self.lidar_frame.clone();
        o.frames.names = self.frames.clone();
        o.frames.all = self.all_frames;
        o.frames.extrinsics = self.extrinsics.clone();
        o.frames.rig_files = self.rig_frames.clone();
        let d = &mut o.detector;
        d.tau = self.tau.tau;
        d.ells = self.ell.ell.clone();
        d.normals.voxel = (self.voxel > 0.0).then_some(self.voxel);
        d.normals.radius = self.normal_radius;
        d.normals.knn = self.knn;
        d.normals.min_neighbours = self.min_neighbours;
        d.normals.viewpoint = self
            .viewpoint
            .as_deref()
            .map(|s| parse_triple(s, "--viewpoint"))
            .transpose()?;
        d.estimate_normals = self.estimate_normals;
        if self.pairs {
            let mut p = RunPairs::default();
            p.step = self.pair_step;
            p.gate = self.gate;
            p.poses = self.poses.clone();
            p.poses_format = self.poses_format;
            p.calib = self.calib.clone();
            p.poses_topic = self.poses_topic.clone();
            p.poses_frame = self.poses_frame.clone();
            o.pairs = Some(p);
        }
        o.threads = self.threads;
        o.load.bag = self.bag.bag_options();
        self.xacro.apply(&mut o.load);
        Ok(o)
    }
}

/// `--csv`, `--jsonl`, `--timeline`: a file name with its extension that
/// the run may write (`check_output_target`: none of its inputs, nor inside
/// an input folder; not a symlink or a file of several names).
fn check_target(flag: &str, target: &Path, ext: &str, inputs: &[PathBuf]) -> Result<()> {
    if !target
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
    {
        return Err(Error::usage(format!(
            "{flag} {}: expected a file name ending in .{ext}",
            target.display()
        )));
    }
    // A run reads every point file of an input folder (a CSV among them),
    // so nothing is written inside one.
    let dir = target.parent().filter(|d| !d.as_os_str().is_empty());
    let real_dir = dir.unwrap_or(Path::new(".")).canonicalize();
    if let Ok(d) = &real_dir {
        if let Some(p) = inputs
            .iter()
            .find(|p| p.is_dir() && p.canonicalize().is_ok_and(|c| d.starts_with(c)))
        {
            return Err(Error::usage(format!(
                "{flag} {}: refusing to write into an input folder of the run ({})",
                target.display(),
                p.display()
            )));
        }
    }
    check_output_target(flag, "run", target, inputs)
}

/// A file written as the scans finish, put in place when the run ends well
/// (the atomic writer's temporary; removed otherwise).
struct Streamed(AtomicFile);

impl Streamed {
    fn create(target: &Path) -> Result<Self> {
        AtomicFile::create(target).map(Streamed)
    }

    fn line(&mut self, s: &str) -> Result<()> {
        writeln!(self.0, "{s}").map_err(|e| self.0.error(e))
    }

    fn finish(self) -> Result<()> {
        self.0.commit()
    }
}

/// Where the records go: the CSV and JSON lines files, standard output
/// for `--format csv`, the MCAP file for `--format mcap`.
struct Sinks<'a> {
    csv: Option<Streamed>,
    jsonl: Option<Streamed>,
    stdout_csv: Option<&'a mut dyn Write>,
    mcap: Option<RunMcap<AtomicFile>>,
    /// The run's transforms until the first scan names the scan frame.
    tf: Option<RunTransforms>,
}

impl Sinks<'_> {
    /// Before the first record: the CSV header, the MCAP's transforms.
    fn begin(&mut self, run: &Run) -> Result<()> {
        if self.mcap.is_some() {
            let (frames, graph) = run_transforms(run);
            self.tf = Some(RunTransforms::new(frames, graph));
        }
        let head = render::csv_line(&run.csv_header());
        if let Some(c) = self.csv.as_mut() {
            c.line(&head)?;
        }
        if let Some(out) = self.stdout_csv.as_mut() {
            stdout_line(*out, &head)?;
        }
        Ok(())
    }

    /// One record, in run order.
    fn record(&mut self, r: &ScanResult) -> Result<()> {
        if self.csv.is_some() || self.stdout_csv.is_some() {
            let row = render::csv_line(&r.csv_row());
            if let Some(c) = self.csv.as_mut() {
                c.line(&row)?;
            }
            if let Some(out) = self.stdout_csv.as_mut() {
                stdout_line(*out, &row)?;
            }
        }
        if let Some(j) = self.jsonl.as_mut() {
            j.line(&r.to_json())?;
        }
        if let Some(m) = self.mcap.as_mut() {
            if let Some(tf) = self.tf.take() {
                m.transforms(tf.resolve(r.frame_id()));
            }
            m.record(scan_record(r))?;
        }
        Ok(())
    }
}

/// The MCAP file's metadata: what the run is, and its summary as
/// `--format json` gives it.
fn mcap_facts(report: &RunReport, warnings: &[Warning]) -> Result<Vec<(String, String)>> {
    let summary = render::render(
        report,
        warnings,
        OutputFormat::Json,
        render::Style::plain(),
        &render::Layout::default(),
    )?;
    // `scans` or `pairs`, as the records name it.
    let unit = serde_json::to_value(report.unit)
        .map_err(|e| Error::new(Code::Io, format!("cannot encode the run's unit: {e}")))?
        .as_str()
        .unwrap_or_default()
        .to_string();
    Ok(vec![
        ("report".into(), "run".into()),
        ("unit".into(), unit),
        ("timeline_topic".into(), RUN_TOPIC.into()),
        ("summary".into(), summary),
    ])
}

fn stdout_line(out: &mut dyn Write, s: &str) -> Result<()> {
    match writeln!(out, "{s}") {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(Error::new(Code::Io, format!("cannot write output: {e}"))),
    }
}

/// `audit run`.
pub fn run(args: &RunArgs, out: &mut dyn Write) -> Result<i32> {
    let format = args.output.format;
    if !matches!(
        format,
        OutputFormat::Table
            | OutputFormat::Markdown
            | OutputFormat::Json
            | OutputFormat::Csv
            | OutputFormat::Svg
            | OutputFormat::Mcap
    ) {
        return Err(Error::usage(format!(
            "--format {}: audit run writes text, markdown, json (the summary), csv (one row per scan), svg (the timeline) or mcap (the timeline for Foxglove)",
            format.name()
        )));
    }
    let opts = args.options()?;
    if args.output.output.is_some() && format == OutputFormat::Csv {
        // The per-scan rows stream as they come; their file is --csv's.
        return Err(Error::usage(
            "--output with --format csv: the per-scan rows are streamed; give --csv FILE",
        ));
    }
    let mcap_target = match (format, &args.output.output) {
        (OutputFormat::Mcap, Some(t)) => Some(t),
        (OutputFormat::Mcap, None) => {
            // Written as the scans finish, going back over its chunks.
            return Err(Error::usage(
                "--format mcap: audit run streams the MCAP file; give --output FILE.mcap",
            ));
        }
        _ => None,
    };
    super::check_output(&args.output, &args.run)?;
    for (flag, t, ext) in [
        ("--csv", &args.csv, "csv"),
        ("--jsonl", &args.jsonl, "jsonl"),
        ("--timeline", &args.timeline, "svg"),
    ] {
        if let Some(t) = t {
            check_target(flag, t, ext, &args.run)?;
        }
    }
    let mut sinks = Sinks {
        csv: args.csv.as_deref().map(Streamed::create).transpose()?,
        jsonl: args.jsonl.as_deref().map(Streamed::create).transpose()?,
        stdout_csv: (format == OutputFormat::Csv).then_some(&mut *out),
        mcap: mcap_target
            .map(|t| AtomicFile::create(t).and_then(RunMcap::new))
            .transpose()?,
        tf: None,
    };
    let mut run = Run::open_with(&args.run, &opts, Arc::new(TermBars))?;
    sinks.begin(&run)?;
    for r in &mut run {
        sinks.record(&r?)?;
    }
    let (report, warnings) = run.finish()?;
    let Sinks {
        csv, jsonl, mcap, ..
    } = sinks;
    for s in [csv, jsonl].into_iter().flatten() {
        s.finish()?;
    }
    if let Some(m) = mcap {
        m.finish(mcap_facts(&report, &warnings)?)?.commit()?;
    }
    print_warnings(&warnings);
    let svg = || {
        render::draw(
            &report.timeline_plot(),
            OutputFormat::Svg,
            render::Style::plain(),
            &render::Layout::default(),
        )
    };
    if let Some(t) = &args.timeline {
        write_atomic(t, svg()?.as_bytes())?;
    }
    match (format, &args.output.output) {
        (OutputFormat::Csv | OutputFormat::Mcap, _) => {}
        (OutputFormat::Svg, Some(t)) => write_atomic(t, svg()?.as_bytes())?,
        (OutputFormat::Svg, None) => stdout_line(out, svg()?.trim_end())?,
        _ => emit_warned(&report, &warnings, &args.output, &args.run, out)?,
    }
    Ok(strict_exit(args.strict, &report))
}

/// `--strict`: 1 when the run lost data (scans or pairs skipped, or a read
/// stopped at damage), said on standard error; else 0. Only this class:
/// the other warnings (`ignored`, `frame-missing`...) leave every scan
/// reported, as `check`'s exit 1 is for problems, not notes.
fn strict_exit(strict: bool, report: &RunReport) -> i32 {
    let skipped: usize = report.skipped.iter().map(|s| s.count).sum();
    if !strict || (skipped == 0 && report.damage.is_none()) {
        return 0;
    }
    let mut lost = Vec::new();
    if skipped > 0 {
        lost.push(format!("{skipped} {} skipped", report.unit.name()));
    }
    if let Some(d) = &report.damage {
        lost.push(format!("the read stopped at damage ({d})"));
    }
    eprintln!("audit run --strict: {}: exit 1", lost.join("; "));
    1
}
