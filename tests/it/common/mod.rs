//! Helpers shared by the test modules.

#![allow(dead_code)] // each module uses some of the helpers

pub mod derived;
pub mod hostile;
pub mod schema;
pub mod testdata;

/// The `audit` binary with `NO_COLOR` set: the one command builder of the suite.
pub fn audit() -> assert_cmd::Command {
    let mut c = assert_cmd::Command::cargo_bin("audit").expect("binary");
    c.env("NO_COLOR", "1");
    c
}

/// Run `audit ARGS`: (exit code, stdout, stderr).
pub fn run_cli(args: &[&str]) -> (i32, String, String) {
    let out = audit().args(args).output().expect("run");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A rig xacro in `dir` that includes `$(find velodyne_description)`'s VLP-16
/// macro (base_link -> lidar, mount origin (0.1, 0, 0.25) turned by pi/2 about
/// z): in a temporary directory the upward package search cannot find the
/// package, so `--package-path` is needed.
pub fn vlp16_rig_xacro(dir: &std::path::Path) -> std::path::PathBuf {
    let input = dir.join("rig.urdf.xacro");
    std::fs::write(
        &input,
        r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find velodyne_description)/urdf/VLP-16.urdf.xacro"/>
  <link name="base_link"/>
  <xacro:VLP-16 parent="base_link" name="lidar">
    <origin xyz="0.1 0 ${0.5 / 2}" rpy="0 0 ${pi / 2}"/>
  </xacro:VLP-16>
</robot>
"#,
    )
    .expect("write");
    input
}

/// A stand-in `xacro` program in `dir` that prints a fixed URDF, base ->
/// lidar at z = 0.5 m, whatever it is given: `--xacro external` with `dir`
/// as the search path (or PATH) runs it.
#[cfg(unix)]
pub fn fake_xacro(dir: &std::path::Path) -> std::path::PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let script = dir.join("xacro");
    std::fs::write(
        &script,
        "#!/bin/sh\nprintf '%s\\n' '<robot name=\"r\">' '<link name=\"base\"/>' '<link name=\"lidar\"/>' '<joint name=\"j\" type=\"fixed\">' '<origin xyz=\"0 0 0.5\"/>' '<parent link=\"base\"/>' '<child link=\"lidar\"/>' '</joint>' '</robot>'\n",
    )
    .expect("write");
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    script
}

/// Every number in a JSON value (nested arrays flattened, row by row).
pub fn nums(v: &serde_json::Value) -> Vec<f64> {
    match v {
        serde_json::Value::Array(a) => a.iter().flat_map(nums).collect(),
        serde_json::Value::Number(n) => vec![n.as_f64().unwrap()],
        _ => panic!("not numbers: {v}"),
    }
}

/// `max |a - b| / max |b|`.
pub fn rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let s = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / s
}
