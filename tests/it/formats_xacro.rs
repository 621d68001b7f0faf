//! A .xacro file is expanded by the `xacro` program when it is on PATH. Here a
//! stand-in `xacro` (a shell script printing a fixed URDF) proves the wiring; the
//! refusal without `xacro` is in the bad-input catalogue (08-macro.urdf.xacro).

#[cfg(unix)]
#[test]
fn xacro_on_path_is_run() {
    use extrinsic_audit::formats::{load_file, LoadOptions};
    use std::os::unix::fs::PermissionsExt;

    let dir = tempfile::tempdir().expect("tempdir");
    let script = dir.path().join("xacro");
    std::fs::write(
        &script,
        "#!/bin/sh\nprintf '%s\\n' '<robot name=\"r\">' '<link name=\"base\"/>' '<link name=\"lidar\"/>' '<joint name=\"j\" type=\"fixed\">' '<origin xyz=\"0 0 0.5\"/>' '<parent link=\"base\"/>' '<child link=\"lidar\"/>' '</joint>' '</robot>'\n",
    )
    .expect("write");
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    let l = load_file(
        std::path::Path::new(
            "tests/fixtures/formats/norlab-warthog-rs32-mti10__warthog.urdf.xacro",
        ),
        &LoadOptions {
            xacro_search_path: Some(dir.path().into()),
            ..LoadOptions::default()
        },
    )
    .expect("expanded");
    assert_eq!(l.edges.len(), 1);
    assert_eq!(l.edges[0].provenance.format, "urdf");
    assert!(l.edges[0].provenance.key.contains("expanded"));
    assert!((l.edges[0].transform.translation().z - 0.5).abs() < 1e-15);
}
