//! Writers (fixtures, round trips, exporting synthetic scenes).

/// Encoding for [`write_ply`] and [`write_pcd`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// Text.
    Ascii,
    /// Binary, little-endian.
    BinaryLittleEndian,
    /// Binary, big-endian.
    BinaryBigEndian,
}

/// CSV with a header `x,y,z,nx,ny,nz[,w]`, full precision.
pub fn write_csv(points: &[[f64; 3]], normals: &[[f64; 3]], weights: Option<&[f64]>) -> Vec<u8> {
    let mut s = String::from(if weights.is_some() {
        "x,y,z,nx,ny,nz,w\n"
    } else {
        "x,y,z,nx,ny,nz\n"
    });
    for i in 0..points.len().min(normals.len()) {
        let p = points[i];
        let n = normals[i];
        s.push_str(&format!(
            "{:?},{:?},{:?},{:?},{:?},{:?}",
            p[0], p[1], p[2], n[0], n[1], n[2]
        ));
        if let Some(w) = weights {
            s.push_str(&format!(",{:?}", w.get(i).copied().unwrap_or(1.0)));
        }
        s.push('\n');
    }
    s.into_bytes()
}

/// One record per point, `x y z nx ny nz` as doubles: ascii (shortest
/// round-trip text) or binary in the given byte order.
fn write_records(out: &mut Vec<u8>, points: &[[f64; 3]], normals: &[[f64; 3]], enc: Encoding) {
    for (p, n) in points.iter().zip(normals) {
        let vals = [p[0], p[1], p[2], n[0], n[1], n[2]];
        match enc {
            Encoding::Ascii => {
                let line: Vec<String> = vals.iter().map(|v| format!("{v:?}")).collect();
                out.extend_from_slice(line.join(" ").as_bytes());
                out.push(b'\n');
            }
            Encoding::BinaryLittleEndian => vals
                .iter()
                .for_each(|v| out.extend_from_slice(&v.to_le_bytes())),
            Encoding::BinaryBigEndian => vals
                .iter()
                .for_each(|v| out.extend_from_slice(&v.to_be_bytes())),
        }
    }
}

/// PLY with double properties `x y z nx ny nz`.
pub fn write_ply(points: &[[f64; 3]], normals: &[[f64; 3]], enc: Encoding) -> Vec<u8> {
    let n = points.len().min(normals.len());
    let fmt = match enc {
        Encoding::Ascii => "ascii",
        Encoding::BinaryLittleEndian => "binary_little_endian",
        Encoding::BinaryBigEndian => "binary_big_endian",
    };
    let mut out = format!(
        "ply\nformat {fmt} 1.0\ncomment written by extrinsic-audit\nelement vertex {n}\nproperty double x\nproperty double y\nproperty double z\nproperty double nx\nproperty double ny\nproperty double nz\nend_header\n"
    )
    .into_bytes();
    write_records(&mut out, points, normals, enc);
    out
}

/// PCD 0.7 with double fields `x y z normal_x normal_y normal_z` (binary is
/// little endian, as PCL writes it; `BinaryBigEndian` is treated as binary).
pub fn write_pcd(points: &[[f64; 3]], normals: &[[f64; 3]], enc: Encoding) -> Vec<u8> {
    let n = points.len().min(normals.len());
    let data = if enc == Encoding::Ascii {
        "ascii"
    } else {
        "binary"
    };
    let mut out = format!(
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 8 8 8 8 8 8\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {data}\n"
    )
    .into_bytes();
    // PCL's binary is little endian.
    let enc = if enc == Encoding::BinaryBigEndian {
        Encoding::BinaryLittleEndian
    } else {
        enc
    };
    write_records(&mut out, points, normals, enc);
    out
}
