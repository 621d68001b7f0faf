//! The tool's own TOML rig format (see calibrations/README.md).
