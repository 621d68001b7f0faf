//! The detector commands' values written as text (`x,y,z`, six numbers, a
//! list of numbers, a scene name), parsed and checked here, beside the options
//! they fill. Every error is a usage error naming the option (`--shift`,
//! `--noise`, ...), as the binary prints it.

use crate::degeneracy::scene::SceneKind;
use crate::diagnostic::{Error, Result};
use crate::geometry::Transform;
use crate::tolerances::MAX_LIST_VALUES;
use nalgebra::Vector6;

/// `x,y,z`: three finite numbers (`what` names the option).
pub fn parse_triple(s: &str, what: &str) -> Result<[f64; 3]> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(Error::usage(format!(
            "{what}: expected three comma-separated numbers x,y,z, found {s:?}"
        )));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = p
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                Error::usage(format!("{what}: expected a finite number, found {p:?}"))
            })?;
    }
    Ok(v)
}

/// The frame `--shift x,y,z` and `--rotate-rpy roll,pitch,yaw` give: its pose
/// `T = (R, d)` in the input frame, `R = Rz(yaw) Ry(pitch) Rx(roll)`
/// (the identity without either).
pub fn parse_frame(shift: Option<&str>, rpy: Option<&str>) -> Result<Transform> {
    let d = match shift {
        Some(s) => parse_triple(s, "--shift")?,
        None => [0.0; 3],
    };
    let r = match rpy {
        Some(s) => parse_triple(s, "--rotate-rpy")?,
        None => [0.0; 3],
    };
    Transform::from_rpy(r, d)
}

/// `--update wx,wy,wz,tx,ty,tz`: a twist, rotation first (rad, m).
pub fn parse_update(s: &str) -> Result<Vector6<f64>> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| Error::usage(format!("--update: expected six numbers, found {s:?}")))?;
    if v.len() != 6 {
        return Err(Error::usage(format!(
            "--update: expected six numbers wx,wy,wz,tx,ty,tz, found {}",
            v.len()
        )));
    }
    Ok(Vector6::from_column_slice(&v))
}

/// `--initial-guess x,y,z,roll,pitch,yaw`: the pose of a pair's source frame
/// in its target frame (m, rad; the rotation as in [`parse_frame`]).
pub fn parse_initial_guess(s: &str) -> Result<Transform> {
    let v = parse_update(s).map_err(|_| {
        Error::usage(format!(
            "--initial-guess: expected six numbers x,y,z,roll,pitch,yaw, found {s:?}"
        ))
    })?;
    Transform::from_rpy([v[3], v[4], v[5]], [v[0], v[1], v[2]])
}

/// A comma-separated list of 1 to [`MAX_LIST_VALUES`] numbers in `[min, max]`.
pub(crate) fn parse_list(s: &str, what: &str, (min, max): (f64, f64)) -> Result<Vec<f64>> {
    let v: Vec<f64> = s
        .split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| {
            p.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && (min..=max).contains(x))
                .ok_or_else(|| {
                    Error::usage(format!(
                        "{what}: expected numbers from {min} to {max}, found {p:?}"
                    ))
                })
        })
        .collect::<Result<_>>()?;
    check_count(v.len(), what)?;
    Ok(v)
}

/// A list's length: 1 to [`MAX_LIST_VALUES`].
pub(crate) fn check_count(n: usize, what: &str) -> Result<()> {
    if n == 0 || n > MAX_LIST_VALUES {
        return Err(Error::usage(format!(
            "{what}: expected 1 to {MAX_LIST_VALUES} values, found {n}"
        )));
    }
    Ok(())
}

/// `--scene tunnel|corridor|corner`.
pub fn parse_scene(s: &str) -> Result<SceneKind> {
    SceneKind::parse(s).ok_or_else(|| {
        Error::usage(format!(
            "--scene: expected tunnel, corridor or corner, found {s:?}"
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triple_is_three_finite_numbers() {
        assert_eq!(
            parse_triple(" 1, -2.5,3e1 ", "--shift").unwrap(),
            [1.0, -2.5, 30.0]
        );
        let e = parse_triple("1,2", "--shift").unwrap_err();
        assert_eq!(
            e.message,
            "--shift: expected three comma-separated numbers x,y,z, found \"1,2\""
        );
        let e = parse_triple("1,inf,2", "--viewpoint").unwrap_err();
        assert_eq!(
            e.message,
            "--viewpoint: expected a finite number, found \"inf\""
        );
    }

    #[test]
    fn an_initial_guess_is_a_translation_then_roll_pitch_yaw() {
        let t = parse_initial_guess("1,2,3,0,0,1.5707963267948966").unwrap();
        let d = t.translation();
        assert_eq!([d.x, d.y, d.z], [1.0, 2.0, 3.0]);
        // yaw pi/2: the source's x axis is the target's y axis.
        let x = t.rotation() * nalgebra::Vector3::x();
        assert!((x - nalgebra::Vector3::y()).norm() < 1e-15, "{x}");
        assert!(parse_initial_guess("1,2,3").is_err());
    }

    #[test]
    fn a_list_keeps_its_range_and_length() {
        assert_eq!(
            parse_list("0, 0.01,", "--noise", (0.0, 1.0)).unwrap(),
            [0.0, 0.01]
        );
        let e = parse_list("2", "--noise", (0.0, 1.0)).unwrap_err();
        assert_eq!(
            e.message,
            "--noise: expected numbers from 0 to 1, found \"2\""
        );
        let e = parse_list("", "--noise", (0.0, 1.0)).unwrap_err();
        assert_eq!(e.message, "--noise: expected 1 to 16 values, found 0");
        let many = vec!["0.1"; 17].join(",");
        assert!(parse_list(&many, "--voxel", (0.02, 10.0)).is_err());
    }
}
