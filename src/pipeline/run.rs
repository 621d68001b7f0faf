//! `audit run`: a recorded run through the detector, scan by scan (or pair
//! by pair), streamed (see [`crate::run`]): the inputs made into a source,
//! the frames and poses resolved, the work queue run, every outcome handed
//! to the caller's sinks (CSV, JSON lines) in order and folded into the
//! summary report.

use super::run_options::{RunOptions, RunPairs};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats;
use crate::formats::bag::{self, BagLimits, Flow, TopicInfo};
use crate::frames::FrameGraph;
use crate::geometry::Transform;
use crate::progress::ProgressFactory;
use crate::report::run::{RunHeader, RunReport, RunSink, RunUnit};
use crate::run::frames::{FrameGroup, Frames, RunFrame};
use crate::run::poses::{self, PoseTrack, ScanKey};
use crate::run::scan::{self, Job, Outcome, ScanMeta, Settings, Skip};
use crate::run::source::{
    self, BagScans, FileScans, ScanItem, ScanSource, SourceEnd, POINTCLOUD2_TYPES,
};
use crate::run::summary::{Shape, Summary};
use crate::run::work::{self, Limits, Submit};
use crate::tolerances::{
    MAX_PAIR_STEP, MAX_RUN_INFLIGHT_CELLS, MAX_SKIP_WARNINGS, RUN_SCANS_PER_WORKER,
};
use std::collections::{BTreeMap, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where the scans come from, and what is known before reading them.
struct Plan {
    source: Box<dyn ScanSource>,
    bags: Vec<PathBuf>,
    topic: Option<String>,
    topics: Vec<TopicInfo>,
    total: Option<u64>,
    first_frame: Option<String>,
    warnings: Vec<Warning>,
}

/// The `PointCloud2` topic: the one asked for, or the only one.
fn choose_topic(bag: &Path, topics: &[TopicInfo], asked: Option<&str>) -> Result<TopicInfo> {
    let clouds: Vec<&TopicInfo> = topics
        .iter()
        .filter(|t| POINTCLOUD2_TYPES.contains(&t.type_name.as_str()))
        .collect();
    let list = |v: &[&TopicInfo]| {
        v.iter()
            .map(|t| crate::sanitize::quote(&t.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some(a) = asked {
        return match topics.iter().find(|t| t.name == a) {
            Some(t) if POINTCLOUD2_TYPES.contains(&t.type_name.as_str()) || t.type_name.is_empty() => Ok(t.clone()),
            Some(t) => Err(Error::usage(format!(
                "--topic {a}: its type is {}, expected sensor_msgs/msg/PointCloud2 (PointCloud2 topics: {})",
                crate::sanitize::quote(&t.type_name),
                if clouds.is_empty() { "none".into() } else { list(&clouds) }
            ))
            .in_file(bag)),
            None => Err(Error::usage(format!(
                "--topic {a}: no such topic (PointCloud2 topics: {})",
                if clouds.is_empty() { "none".into() } else { list(&clouds) }
            ))
            .in_file(bag)),
        };
    }
    match clouds.as_slice() {
        [one] => Ok((*one).clone()),
        [] => Err(Error::usage(format!(
            "expected a sensor_msgs/msg/PointCloud2 topic, found none (topics: {})",
            topics
                .iter()
                .map(|t| t.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ))
        .in_file(bag)),
        many => Err(Error::usage(format!(
            "{} PointCloud2 topics: choose one with --topic ({})",
            many.len(),
            list(many)
        ))
        .in_file(bag)),
    }
}

/// The frame of the topic's first message (its header alone).
fn first_frame(bags: &[PathBuf], topic: &str, limits: BagLimits) -> Option<String> {
    let mut frame = None;
    for b in bags {
        let _ = bag::stream(b, &|t| t == topic, limits, &mut |m| {
            frame = bag::pointcloud2::decode(&m.data, m.encoding)
                .ok()
                .map(|c| c.frame_id.trim_start_matches('/').to_string());
            Ok(Flow::Stop)
        });
        if frame.is_some() {
            break;
        }
    }
    frame
}

fn plan(inputs: &[PathBuf], opts: &RunOptions) -> Result<Plan> {
    let limits = BagLimits::default();
    let scans = &opts.scans;
    if inputs.is_empty() {
        return Err(Error::usage(
            "expected a run: a bag, a KITTI sequence, a folder or a list of point files",
        ));
    }
    let all_bags = inputs.iter().all(|p| bag::is_bag(p) && !is_sequence_dir(p));
    if all_bags {
        let listing = bag::topics(&inputs[0])?;
        let t = choose_topic(&inputs[0], &listing.topics, scans.topic.as_deref())?;
        let first = first_frame(inputs, &t.name, limits);
        let source = BagScans {
            bags: inputs.to_vec(),
            topic: t.name.clone(),
            window: scans.window,
            limits,
        };
        return Ok(Plan {
            source: Box::new(source),
            bags: inputs.to_vec(),
            topic: Some(t.name),
            topics: listing.topics,
            total: t.count.filter(|_| inputs.len() == 1),
            first_frame: first,
            warnings: listing.warnings,
        });
    }
    if scans.topic.is_some() {
        return Err(Error::usage(
            "--topic applies to bags; these inputs are a sequence of files",
        ));
    }
    let files = source::sequence_files(inputs)?;
    let times = source::kitti_times(&files)?;
    let mut warnings = Vec::new();
    let times = match times {
        Some((path, t)) if t.len() < files.len() => {
            warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!(
                        "{} times for {} scans: the times are not used",
                        t.len(),
                        files.len()
                    ),
                )
                .at(&Location::file(&path)),
            );
            None
        }
        Some((_, t)) => Some(t),
        None => None,
    };
    if scans.window.needs_times() && times.is_none() {
        return Err(Error::usage(
            "--start/--end in seconds need the scans' times (a KITTI times.txt); give scan indices instead",
        ));
    }
    let total = Some(files.len() as u64);
    let source = FileScans {
        what: describe_files(inputs, files.len()),
        files,
        times,
        frame_id: scans.lidar_frame.clone(),
        window: scans.window,
    };
    Ok(Plan {
        source: Box::new(source),
        bags: Vec::new(),
        topic: None,
        topics: Vec::new(),
        total,
        first_frame: scans.lidar_frame.clone(),
        warnings,
    })
}

/// A KITTI sequence folder (`velodyne/` inside) is never a bag.
fn is_sequence_dir(p: &Path) -> bool {
    p.is_dir() && !p.join("metadata.yaml").is_file()
}

fn describe_files(inputs: &[PathBuf], n: usize) -> String {
    match inputs {
        [one] => format!("{} ({n} scans)", one.display()),
        _ => format!("{} files", n),
    }
}

/// The run's transforms: the bags' (when they have any) and the extrinsics
/// files'.
fn transforms(
    opts: &RunOptions,
    bags: &[PathBuf],
    notes: &mut Vec<Warning>,
) -> Result<Option<FrameGraph>> {
    let mut graph = FrameGraph::new();
    let mut any = false;
    for b in bags {
        match formats::load_file(b, &opts.load) {
            Ok(l) => {
                graph.add(l)?;
                any = true;
            }
            // A bag without /tf_static or a description, or one too damaged
            // to read them, is a run without transforms: the scans are still
            // read (up to the damage, which the read reports).
            Err(e) if e.code != Code::Usage => {
                let what = if e.message.starts_with("bag: expected transforms") {
                    e.message.clone()
                } else {
                    format!("its transforms could not be read ({})", e.message)
                };
                let msg = format!("{what}: the scans are reported in their own frame");
                notes.push(Warning::new(Code::FrameMissing, msg).at(&Location::file(b)));
            }
            Err(e) => return Err(e),
        }
    }
    for f in &opts.frames.extrinsics {
        graph.add(formats::load_file(f, &opts.load)?)?;
        any = true;
    }
    notes.extend(graph.warnings().iter().cloned());
    Ok(any.then_some(graph))
}

/// The body frames asked for (or the default: the roots of the scan frame's
/// tree), then the rig frames.
fn frame_list(
    opts: &RunOptions,
    graph: Option<&FrameGraph>,
    first: Option<&str>,
) -> Result<Vec<RunFrame>> {
    let mut list = vec![RunFrame {
        name: "scan".into(),
        group: FrameGroup::Scan,
        fixed: Some(Transform::identity()),
        source: "the scan's own frame (header.frame_id)".into(),
    }];
    let named: Vec<String> = match (graph, first) {
        _ if !opts.frames.names.is_empty() => opts.frames.names.clone(),
        (Some(g), Some(f)) if opts.frames.all => {
            g.frames().into_iter().filter(|n| n != f).collect()
        }
        (Some(g), Some(f)) => g
            .roots()
            .into_iter()
            .filter(|r| r != f && g.transform(f, r).is_ok())
            .collect(),
        _ => Vec::new(),
    };
    for n in named {
        if n == "scan" || list.iter().any(|f| f.name == n) {
            return Err(Error::usage(format!(
                "--frame {n}: named twice (or `scan`, the scan frame's own name)"
            )));
        }
        let known = graph.is_some_and(|g| g.contains(&n));
        if !known {
            let frames = graph
                .map(|g| g.frames().join(", "))
                .unwrap_or_else(|| "none".into());
            return Err(Error::usage(format!(
                "--frame {n}: the run's transforms do not name it (frames: {frames}; a bag's /tf_static and /robot_description, and --extrinsics FILE)"
            )));
        }
        list.push(RunFrame {
            name: n,
            group: FrameGroup::Named,
            fixed: None,
            source: "the run's transforms".into(),
        });
    }
    list.extend(rig_frames(opts)?);
    Ok(list)
}

/// `--rig-frames`: every rig file that counts in the statistics (not a
/// placeholder, not a duplicate) gives its body frame `T^-1` and its lever
/// arm alone.
fn rig_frames(opts: &RunOptions) -> Result<Vec<RunFrame>> {
    if opts.frames.rig_files.is_empty() {
        return Ok(Vec::new());
    }
    let is_rig = |p: &Path| {
        p.extension().is_some_and(|e| e == "toml")
            && p.file_name().is_some_and(|n| n != "audit.toml")
    };
    let files = super::files::expand_paths(&opts.frames.rig_files, is_rig)?;
    let mut out = Vec::new();
    for f in files {
        let loaded = formats::load_file(&f, &opts.load)?;
        let Some(meta) = loaded
            .rig
            .clone()
            .filter(|m| m.in_statistics() && !m.from.is_empty() && !m.to.is_empty())
        else {
            continue;
        };
        let mut g = FrameGraph::new();
        g.add(loaded)?;
        let t = g
            .transform(&meta.from, &meta.to)
            .map_err(|e| e.in_file(&f))?
            .transform;
        let body = t.inverse();
        let lever = Transform::from_translation((*body.translation()).into())?;
        let source = format!("{} ({} -> {})", f.display(), meta.from, meta.to);
        out.push(RunFrame {
            name: meta.id.clone(),
            group: FrameGroup::Rig,
            fixed: Some(body),
            source: source.clone(),
        });
        out.push(RunFrame {
            name: format!("lever:{}", meta.id),
            group: FrameGroup::Lever,
            fixed: Some(lever),
            source,
        });
    }
    if out.is_empty() {
        return Err(Error::usage("--rig-frames: no rig file (a TOML rig with [rig] from and to, not a placeholder or a duplicate) found"));
    }
    Ok(out)
}

/// The poses of a pair run: a file, a bag topic, or the bag's `/tf` (or its
/// only Odometry topic) when none is named.
fn pose_track(
    opts: &RunPairs,
    plan: &Plan,
    frames: &Frames,
    warnings: &mut Vec<Warning>,
) -> Result<PoseTrack> {
    if let Some(path) = &opts.poses {
        let calib = opts.calib.as_deref();
        let mut t = poses::read_file(path, opts.poses_format, calib, warnings)?;
        t.frame = opts.poses_frame.clone();
        return Ok(t);
    }
    if plan.bags.is_empty() {
        return Err(Error::usage(
            "--pairs needs the scans' poses: give --poses FILE (and --poses-format)",
        ));
    }
    let odometry: Vec<&TopicInfo> = plan
        .topics
        .iter()
        .filter(|t| t.type_name.contains("nav_msgs") && t.type_name.ends_with("Odometry"))
        .collect();
    let topic = match &opts.poses_topic {
        Some(t) => t.clone(),
        None if plan.topics.iter().any(|t| t.name == "/tf") => "/tf".into(),
        None if odometry.len() == 1 => odometry[0].name.clone(),
        None => {
            return Err(Error::usage(format!(
                "--pairs needs the scans' poses: give --poses-topic TOPIC (/tf or a nav_msgs/Odometry topic) or --poses FILE (Odometry topics: {})",
                if odometry.is_empty() { "none".into() } else { odometry.iter().map(|t| t.name.as_str()).collect::<Vec<_>>().join(", ") }
            ))
            .in_file(&plan.bags[0]))
        }
    };
    let is_tf = plan
        .topics
        .iter()
        .any(|t| t.name == topic && t.type_name.contains("TFMessage"));
    let child = match (&opts.poses_frame, is_tf) {
        (Some(f), _) => Some(f.clone()),
        (None, true) => Some(tree_root(frames, plan.first_frame.as_deref())),
        (None, false) => None,
    };
    let limits = BagLimits::default();
    poses::read_bag(&plan.bags, &topic, child.as_deref(), limits, warnings)
}

/// The root of the scan frame's static tree (the frame `/tf` moves), or the
/// scan frame itself.
fn tree_root(frames: &Frames, first: Option<&str>) -> String {
    let Some(f) = first else { return String::new() };
    let Some(g) = frames.graph() else {
        return f.to_string();
    };
    g.roots()
        .into_iter()
        .find(|r| g.transform(r, f).is_ok())
        .unwrap_or_else(|| f.to_string())
}

/// The pose of a scan's frame in the poses' fixed frame.
fn scan_pose(
    track: &PoseTrack,
    frames: &Frames,
    item: &ScanItem,
) -> std::result::Result<Transform, String> {
    let key = ScanKey {
        index: item.index,
        stamp_ns: item.stamp_ns,
        time_s: item.time_s,
        file: &item.file,
    };
    let p = track.at(key)?;
    let (Some(of), Some(scan)) = (&track.frame, &item.frame_id) else {
        return Ok(p);
    };
    match frames.pose(of, scan) {
        Some(mount) => Ok(p.compose(&mount)),
        None => Err(format!(
            "the poses are of frame `{}`, which the run's transforms do not connect to the scan frame `{}`",
            crate::sanitize::quote(of),
            crate::sanitize::quote(scan)
        )),
    }
}

/// What the producer thread hands back.
struct Produced {
    end: SourceEnd,
    frames: Frames,
}

/// The producer: every scan of the source as a job (or, for pairs, every
/// scan with the one `step` before it).
fn produce(
    mut source: Box<dyn ScanSource>,
    mut frames: Frames,
    pairs: Option<(usize, &PoseTrack)>,
    submit: &mut Submit<Job>,
) -> Result<Produced> {
    let mut ring: VecDeque<Arc<ScanItem>> = VecDeque::new();
    let end = source.scans(&mut |item: ScanItem| {
        let item = Arc::new(item);
        let poses = frames.poses_for(item.frame_id.as_deref());
        let Some((step, track)) = pairs else {
            let cells = item.cells;
            return Ok(submit(Job::Scan(item, poses), cells));
        };
        ring.push_back(item.clone());
        if ring.len() <= step {
            return Ok(Flow::Continue);
        }
        let target = ring.pop_front().expect("ring holds step + 1 scans");
        let guess = match (
            scan_pose(track, &frames, &target),
            scan_pose(track, &frames, &item),
        ) {
            (Ok(a), Ok(b)) => Ok(a.inverse().compose(&b)),
            (Err(e), _) => Err(format!("target scan {}: {e}", target.index)),
            (_, Err(e)) => Err(format!("source scan {}: {e}", item.index)),
        };
        let job = Job::Pair(target, item, guess, poses);
        let cells = job.cells();
        Ok(submit(job, cells))
    })?;
    Ok(Produced { end, frames })
}

/// Per-scan warnings, each message counted once with the first scans it
/// concerned (a message repeated on every scan is one line), given out in
/// the order of the first scan each concerns (never the messages' order).
#[derive(Default)]
struct ScanWarnings {
    by_message: BTreeMap<String, (Warning, usize, Vec<usize>)>,
    skips: BTreeMap<Skip, usize>,
    /// Each warning with the index of the first scan it concerns.
    out: Vec<(usize, Warning)>,
}

impl ScanWarnings {
    fn add(&mut self, o: &Outcome, unit: RunUnit) {
        let at = o.scan.index;
        if let Some((why, msg)) = &o.skipped {
            let n = self.skips.entry(*why).or_default();
            *n += 1;
            if *n <= MAX_SKIP_WARNINGS {
                let what = unit.describe(&o.scan, o.target.as_ref());
                let w = Warning::new(
                    Code::ScanSkipped,
                    format!("{what}: skipped ({}): {msg}", why.name()),
                );
                self.out.push((at, w));
            }
            return;
        }
        for w in &o.warnings {
            let e = self
                .by_message
                .entry(w.message.clone())
                .or_insert_with(|| (w.clone(), 0, Vec::new()));
            e.1 += 1;
            if e.2.len() < 5 {
                e.2.push(at);
            }
        }
    }

    fn finish(mut self) -> Vec<Warning> {
        for (_, (mut w, n, at)) in std::mem::take(&mut self.by_message) {
            let list: Vec<String> = at.iter().map(usize::to_string).collect();
            let more = if n > at.len() {
                format!(" and {} more", n - at.len())
            } else {
                String::new()
            };
            w.message = format!("scan {}{more}: {}", list.join(", "), w.message);
            self.out.push((at[0], w));
        }
        // Stable: a scan's skip comes before its other warnings, as it came.
        self.out.sort_by_key(|(at, _)| *at);
        let mut out: Vec<Warning> = self.out.into_iter().map(|(_, w)| w).collect();
        for (s, n) in &self.skips {
            if *n > MAX_SKIP_WARNINGS {
                out.push(Warning::new(
                    Code::ScanSkipped,
                    format!(
                        "{} more skipped ({}): listed in the summary, the CSV and the JSON lines",
                        n - MAX_SKIP_WARNINGS,
                        s.name()
                    ),
                ));
            }
        }
        out
    }
}

/// Run `opts`: every outcome to `sink` in run order; the summary report and
/// the warnings (for standard error).
pub fn run(
    inputs: &[PathBuf],
    opts: &RunOptions,
    sink: &mut dyn RunSink,
    bars: &dyn ProgressFactory,
) -> Result<(RunReport, Vec<Warning>)> {
    let settings = &opts.settings()?;
    let plan = plan(inputs, opts)?;
    let mut warnings = plan.warnings.clone();
    let graph = transforms(opts, &plan.bags, &mut warnings)?;
    let list = frame_list(opts, graph.as_ref(), plan.first_frame.as_deref())?;
    let frames = Frames::new(list, graph);
    let step = match opts.pairs.as_ref().map(|p| p.step) {
        Some(s) if !(1..=MAX_PAIR_STEP).contains(&s) => {
            return Err(Error::usage(format!(
                "--pair-step {s}: expected 1 to {MAX_PAIR_STEP}"
            )))
        }
        other => other,
    };
    let track = match &opts.pairs {
        Some(p) => Some(pose_track(p, &plan, &frames, &mut warnings)?),
        None => None,
    };
    let unit = if step.is_some() {
        RunUnit::Pairs
    } else {
        RunUnit::Scans
    };
    let header = RunHeader::new(unit, &frames.list, &settings.rules);
    let mut summary = Summary::new(Shape {
        frames: frames.list.len(),
        drawn: header.drawn_frames(),
        families: settings.rules.len(),
        point_displacement: header.point_displacement(),
    });
    sink.frames(&frames.list, frames.graph())?;
    sink.begin(&header)?;
    let threads = match opts.threads {
        // AUDIT_JOBS or the cores, as check and survey choose.
        0 => super::parallel::threads(),
        n => n,
    };
    let lim = Limits {
        threads,
        depth: threads * RUN_SCANS_PER_WORKER,
        budget: MAX_RUN_INFLIGHT_CELLS,
    };
    let progress = bars.progress();
    progress.start(
        plan.total.unwrap_or(0),
        if step.is_some() {
            "scan pairs"
        } else {
            "scans"
        },
    );
    let mut sw = ScanWarnings::default();
    let what = plan.source.describe();
    let pairs = step.zip(track.as_ref());
    let produced = work::ordered(
        lim,
        |submit: &mut Submit<Job>| produce(plan.source, frames, pairs, submit),
        &|job: &Job| scan::run(job, settings),
        &|job: &Job| panicked(job, settings),
        &mut |o: Outcome| {
            progress.advance(1);
            summary.add(&o);
            sw.add(&o, unit);
            sink.outcome(&header, &o)
        },
    );
    progress.finish();
    let produced = produced?;
    summary.finish();
    warnings.extend(produced.frames.warnings);
    warnings.extend(produced.end.warnings);
    warnings.extend(sw.finish());
    if let Some(d) = &produced.end.damage {
        warnings.push(
            Warning::new(
                Code::RunDamaged,
                format!("{}; the {} before it are reported", d.message, unit.name()),
            )
            .at(&d.location),
        );
    }
    let report = RunReport::new(
        &header,
        &summary,
        crate::report::run::RunContext {
            source: what,
            topic: plan.topic.clone(),
            poses: track.as_ref().map(|t| t.what.clone()),
            settings,
            pair_step: step,
            window: opts.scans.window,
            damage: produced.end.damage.map(|d| d.to_string()),
        },
    );
    Ok((report, warnings))
}

/// The outcome of a job whose worker panicked (a bug): skipped, named.
fn panicked(job: &Job, s: &Settings) -> Outcome {
    let (meta, target) = match job {
        Job::Scan(i, _) => (ScanMeta::of(i), None),
        Job::Pair(t, i, ..) => (ScanMeta::of(i), Some(ScanMeta::of(t))),
    };
    let frames = match job {
        Job::Scan(_, f) | Job::Pair(.., f) => f.len(),
    };
    let _ = s;
    Outcome {
        scan: meta,
        target,
        skipped: Some((
            Skip::Unusable,
            "the analysis of this scan failed unexpectedly (a bug: please report it with the scan)"
                .into(),
        )),
        cells: None,
        nonfinite: None,
        points: 0,
        normals: None,
        pair: None,
        frames: vec![None; frames],
        warnings: Vec::new(),
    }
}
