//! Unstable: the crate's inner parts, for its own tests, benchmarks, fuzz
//! targets and examples, and for the few command-line matters of the `audit`
//! binary that the crate docs name. Not part of the face: no stability and
//! no documentation promise; anything here may change or go in any release.
//! Use the items at the crate root instead.
//!
//! Each module below mirrors a module of the crate and lists, by name, the
//! items something outside the library uses; what is not listed is private.

#![allow(missing_docs)]

pub mod api {
    pub use crate::api::{run_transforms, scan_record};
}

pub mod analysis {
    pub mod metric {
        pub use crate::analysis::metric::{
            adapted_metric, adapted_metric_matrix, family_verdicts, AdaptedReason, VerdictReason,
        };
    }
}

pub mod degeneracy {
    pub use crate::degeneracy::{
        analyse, canonical_basis, check_transport, classify_subspace, correction_difference,
        footprint, footprint_flags, footprint_scores, frame_sweep, generalized_eigen,
        generalized_eigen_raw, paper_frame_changes, reexpress, rel_diff, subspace_angle, transport,
        Accumulator, Analysis, Arm, Assembly, Kernel, MetricRule, TwistScrew, BLOCK,
    };
    pub use crate::degeneracy::{FrameChange, GenEigen, ScoredScrew, SweepRow, TransportCheck};

    pub mod normals {
        pub use crate::degeneracy::normals::{
            estimate_normals_progress, estimate_normals_with, NormalParams, NormalStats,
        };
    }

    pub mod pairs {
        pub use crate::degeneracy::pairs::{pair_assembly, PairStats};
    }

    pub mod points {
        pub use crate::degeneracy::points::{
            accumulate_file, accumulate_file_with, accumulate_reader, parse_points, parse_xyz,
            read_from, read_points, read_points_with, read_xyz, read_xyz_classes, read_xyz_with,
            write_csv, write_pcd, write_ply, Accumulated, Encoding, PointData, PointFormat,
        };
    }

    pub mod scene {
        pub use crate::degeneracy::scene::{
            random_cloud, sample_scene, synthesize, tunnel_exact, voxel_downsample, Cloud,
            Preprocess, SceneKind, SceneRng, SCENE_LENGTH, TUNNEL_RADIUS,
        };
    }

    pub mod threshold {
        pub use crate::degeneracy::threshold::{
            calibrate, count_interval, default_threshold, Calibration, Config, ConfigResult,
            FamilyResult, Interval, SEEDS,
        };
    }
}

pub mod formats {
    pub use crate::formats::{
        all_formats, detect_file, detect_format, load_bytes, load_file, load_str, Parsed, FORMATS,
    };

    pub mod bag {
        pub use crate::formats::bag::*;
    }

    pub mod spec {
        pub use crate::formats::spec::{Confidence, FormatSpec, Input, RigMeta};
    }

    pub mod glim {
        pub use crate::formats::glim::strip_json_comments;
    }

    pub mod rig_toml {
        pub use crate::formats::rig_toml::parse;
    }
}

pub mod frames {
    pub use crate::frames::{EdgeSet, FrameDecl, FrameGraph, RedundantEdge};
}

pub mod geometry {
    pub mod certificate {
        pub use crate::geometry::certificate::{
            adjoint_singular_values, adjoint_summary, ata_minus_i_rel, band, certificates,
            certifies_no_crossing, delta_eff, sigma_max, sigma_min,
        };
    }

    pub mod se3 {
        pub use crate::geometry::se3::{rpy_to_matrix, skew};
    }

    pub mod uncertainty {
        pub use crate::geometry::uncertainty::{
            chain_covariance, compose_steps, literal_half_unit, outputs, propagate,
            rounding_covariance, rounding_std, rpy_covariance, tangent_between, tuple_half_units,
            ChainUncertainty, Outputs, Step,
        };
    }
}

pub mod pipeline {
    pub use crate::pipeline::{
        check_output_target, check_plot_target, check_spread_plot_target, load, write_atomic,
        write_spread_plot, write_survey_plot, Loaded,
    };

    pub mod files {
        pub use crate::pipeline::files::AtomicFile;
    }

    pub mod manifest {
        pub use crate::pipeline::manifest::parse_pair;
    }

    pub mod detector {
        pub use crate::pipeline::detector::{
            calibrate, degeneracy, parse_frame, parse_initial_guess, parse_scene, parse_triple,
            parse_update, read_scan, simulate, simulate_transform, tunnel, wilson95,
            CalibrateOptions, KeptCloud, Scan, ScanOptions, ScanPair, SimulateParams, SimulateRig,
            TunnelParams,
        };
    }
}

pub mod render {
    pub use crate::render::{csv_line, draw, render, ColorChoice, Layout, Style};

    pub mod mcap {
        pub use crate::render::mcap::{RunMcap, RUN_TOPIC};
    }

    pub mod layout {
        pub use crate::render::layout::{wrap, MIN_TERMINAL_WIDTH};
    }
}

pub mod report {
    pub mod detector {
        pub use crate::report::detector::{
            AnalyticCounts, ConfigJson, CorrectionJson, FamilyCalibration, FamilyComparison,
            FromTo, HmJson, IntervalJson, PerScene, SimulateReport, ThresholdReport,
            TunnelFrameJson, TunnelReport,
        };
    }

    pub mod run {
        pub use crate::report::run::{
            FamilyRecord, FrameRecord, PairRecord, RunHeader, RunReport, RunSink, ScanRecord,
        };
    }

    pub mod run_scene {
        pub use crate::report::run_scene::RunTransforms;
    }
}

pub mod run {
    pub mod frames {
        pub use crate::run::frames::RunFrame;
    }

    pub mod poses {
        pub use crate::run::poses::PoseFormat;
    }

    pub mod scan {
        pub use crate::run::scan::{
            FamilyResult, NormalsFrom, Outcome, PairOutcome, ScanMeta, Settings, Skip,
        };
    }

    pub mod source {
        pub use crate::run::source::{Payload, ScanBound, ScanItem, ScanWindow};
    }
}

pub mod sanitize {
    pub use crate::sanitize::line;
}

pub mod tolerances {
    pub use crate::tolerances::{
        DEFAULT_DIFF_ROTATION_TOL_DEG, DEFAULT_DIFF_TRANSLATION_TOL_MM, DEFAULT_ELLS,
        DEFAULT_MAX_FILE_SIZE, DEFAULT_MAX_ROTATION_DRIFT_DEG, DEFAULT_MAX_TRANSLATION_DRIFT,
        DEFAULT_PITCH_TOL, DEFAULT_TAU, ELL_RANGE_M, KAPPA_RANGE, MAX_COORDINATE, MAX_ELLS,
        MAX_JOINT_VALUE, MAX_MESSAGE_CHARS, MAX_SCAN_CELLS, MAX_SIGMA_R_DEG, MAX_SIGMA_T_M,
        MAX_SIM_NOISE_M, MAX_TRANSLATION_M, PAIR_GATE_M, PROGRESS_MIN_BYTES, RAW_MIN_NEIGHBOURS,
        RAW_NORMAL_RADIUS_M, RAW_VOXEL_RANGE_M, RUN_VOXEL_M, SIM_VOXEL_RANGE_M, SMALL_ROTATION_DEG,
    };
}
