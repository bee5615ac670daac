//! Scene keys set from outside the file: a campaign's variants and the
//! library's [`crate::api::load_scene_with`] change dotted keys of the
//! scene's TOML before it is validated, so every override passes the same
//! checks (and error lines) as the file itself.

use std::path::Path;

use crate::error::FlankError;

/// Sets a dotted scene key (`pinion.micro.tip_relief_um`,
/// `analyses.ltca.misalignment_urad.0`): tables are created where absent,
/// numeric parts index existing arrays.
pub fn set_key(
    t: &mut toml::Table,
    key: &str,
    value: toml::Value,
) -> std::result::Result<(), String> {
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur: &mut toml::Value = t.entry(parts[0]).or_insert_with(|| {
        if parts.len() > 1 {
            toml::Value::Table(Default::default())
        } else {
            toml::Value::Boolean(false)
        }
    });
    for (i, p) in parts.iter().enumerate().skip(1) {
        let last = i + 1 == parts.len();
        cur = match cur {
            toml::Value::Table(tab) => tab.entry(*p).or_insert_with(|| {
                if last {
                    toml::Value::Boolean(false)
                } else {
                    toml::Value::Table(Default::default())
                }
            }),
            toml::Value::Array(a) => {
                let n = a.len();
                let k: usize = p.parse().map_err(|_| {
                    format!(
                        "`{}` is an array: index it with a number",
                        parts[..i].join(".")
                    )
                })?;
                a.get_mut(k)
                    .ok_or_else(|| format!("index {k} beyond the array's {n} values"))?
            }
            _ => {
                return Err(format!(
                    "`{}` is a value, not a table",
                    parts[..i].join(".")
                ))
            }
        };
    }
    *cur = value;
    Ok(())
}

/// Parses the scene text `text` (of the file `path`) with each dotted key of
/// `overrides` set to its value (tables created where absent) and validates
/// it as [`crate::scene::parse_scene`] does. The file itself is checked
/// first, so its errors name its own lines; an override that cannot be set,
/// or a value the scene's checks refuse, is a Parse error that names the
/// override (its line number is then that of the scene as rewritten with
/// the overrides).
pub fn parse_scene_with(
    text: &str,
    path: &Path,
    overrides: &[(&str, toml::Value)],
) -> Result<crate::scene::Scene, FlankError> {
    let scene = crate::scene::parse_scene(text, path)?;
    if overrides.is_empty() {
        return Ok(scene);
    }
    let parse = |line: usize, message: String| FlankError::Parse {
        file: path.to_path_buf(),
        line,
        message,
    };
    let mut t: toml::Table = toml::from_str(text).map_err(|e| parse(1, e.to_string()))?;
    for (key, value) in overrides {
        set_key(&mut t, key, value.clone())
            .map_err(|e| parse(1, format!("override `{key}`: {e}")))?;
    }
    let keys: Vec<&str> = overrides.iter().map(|(k, _)| *k).collect();
    let rewritten = toml::to_string(&t).map_err(|e| parse(1, format!("overridden scene: {e}")))?;
    crate::scene::parse_scene(&rewritten, path).map_err(|e| match e {
        FlankError::Parse {
            file,
            line,
            message,
        } => FlankError::Parse {
            file,
            line,
            message: format!("with the overrides {}: {message}", keys.join(", ")),
        },
        other => other,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_reach_the_scene_and_bad_ones_name_the_key() {
        let path = Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/papers/seed002-spur/scene.toml"
        ));
        let text = std::fs::read_to_string(path).unwrap();
        let base = parse_scene_with(&text, path, &[]).unwrap();
        let s = parse_scene_with(
            &text,
            path,
            &[("load.torque_nm", toml::Value::Float(100.0))],
        )
        .unwrap();
        assert!((s.load.torque_nmm - 100_000.0).abs() < 1e-9);
        assert!((base.load.torque_nmm - 312_000.0).abs() < 1e-9);
        let e = parse_scene_with(&text, path, &[("load.torque_nm", toml::Value::Float(-1.0))])
            .unwrap_err()
            .to_string();
        assert!(e.contains("with the overrides load.torque_nm"), "{e}");
        let e = parse_scene_with(
            &text,
            path,
            &[("load.torque_nm.x", toml::Value::Integer(1))],
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("override `load.torque_nm.x`") && e.contains("not a table"),
            "{e}"
        );
    }

    #[test]
    fn set_key_creates_tables_and_indexes_arrays() {
        let mut t: toml::Table = toml::from_str("[a]\nx = [1.0, 2.0]\ny = 3\n").unwrap();
        set_key(&mut t, "a.x.1", toml::Value::Float(5.0)).unwrap();
        set_key(&mut t, "b.c.d", toml::Value::Integer(1)).unwrap();
        assert_eq!(t["a"]["x"][1].as_float(), Some(5.0));
        assert_eq!(t["b"]["c"]["d"].as_integer(), Some(1));
        assert!(set_key(&mut t, "a.y.z", toml::Value::Integer(1))
            .unwrap_err()
            .contains("not a table"));
        assert!(set_key(&mut t, "a.x.7", toml::Value::Integer(1))
            .unwrap_err()
            .contains("beyond"));
    }
}
