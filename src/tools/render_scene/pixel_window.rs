//! `--pixelbounds` and `--cropwindow`, the part of the image to render.
//!
//! pbrt-v4 takes each as one comma-separated argument
//! (`--pixelbounds 0,120,0,90`, `--cropwindow 0,0.5,0,0.5`, also written
//! `--pixelbounds=0,120,0,90`); rpbrt also takes the four values as separate
//! arguments. [`expand_comma_lists`] rewrites pbrt-v4's form as the second
//! before clap reads the command line; [`pixel_bounds`] and [`crop_window`]
//! then check the values. As pbrt-v4 (whose bounds order their corners),
//! `x1 x0` is read as `x0 x1`.

use crate::error::Error;
use std::ffi::OsString;

/// The flags whose four values pbrt-v4 writes as one comma-separated list.
const LIST_FLAGS: [&str; 2] = ["--pixelbounds", "--cropwindow"];

/// The command line with each `--pixelbounds a,b,c,d` (or `=a,b,c,d`) and
/// `--cropwindow a,b,c,d` given as the flag and four arguments. A list of
/// other than four values is an error naming the flag.
pub fn expand_comma_lists(
    args: impl IntoIterator<Item = OsString>,
) -> Result<Vec<OsString>, Error> {
    let mut out = Vec::new();
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        if arg == "--" {
            out.push(arg);
            out.extend(args);
            break;
        }
        let text = arg.to_str().unwrap_or_default();
        if let Some((flag, list)) = text.split_once('=') {
            if LIST_FLAGS.contains(&flag) {
                out.push(flag.into());
                out.extend(split_list(flag, list)?);
                continue;
            }
        }
        let is_list_flag = LIST_FLAGS.contains(&text);
        out.push(arg.clone());
        if is_list_flag {
            match args.next() {
                Some(next) if next.to_str().is_some_and(|v| v.contains(',')) => {
                    out.extend(split_list(text, next.to_str().unwrap_or_default())?)
                }
                Some(next) => out.push(next),
                None => {}
            }
        }
    }
    Ok(out)
}

/// `"a,b,c,d"` → its four values.
fn split_list(flag: &str, list: &str) -> Result<Vec<OsString>, Error> {
    let values: Vec<OsString> = list.split(',').map(|v| v.trim().into()).collect();
    if values.len() != 4 {
        return Err(Error::Usage(format!(
            "{flag} takes four values, x0,x1,y0,y1 (or x0 x1 y0 y1); \"{list}\" has {}",
            values.len()
        )));
    }
    Ok(values)
}

/// Pixel bounds from `--pixelbounds x0 x1 y0 y1`: `[x0, x1, y0, y1]` with
/// `x0 < x1` and `y0 < y1`. Bounds with no pixels are an error. (Bounds
/// reaching outside the image are clipped to it when the film is known.)
pub fn pixel_bounds(values: &[i32]) -> Result<[i32; 4], Error> {
    let &[a, b, c, d] = values else {
        return Err(Error::Usage(format!(
            "--pixelbounds takes four values, not {}",
            values.len()
        )));
    };
    let bounds = [a.min(b), a.max(b), c.min(d), c.max(d)];
    if bounds[0] == bounds[1] || bounds[2] == bounds[3] {
        return Err(Error::Usage(format!(
            "--pixelbounds {a},{b},{c},{d} holds no pixels (x0 x1 y0 y1: each pair must differ)"
        )));
    }
    Ok(bounds)
}

/// A crop window from `--cropwindow x0 x1 y0 y1`: fractions of the image
/// in [0, 1], `[x0, x1, y0, y1]` with `x0 < x1` and `y0 < y1`.
pub fn crop_window(values: &[f64]) -> Result<[f64; 4], Error> {
    let &[a, b, c, d] = values else {
        return Err(Error::Usage(format!(
            "--cropwindow takes four values, not {}",
            values.len()
        )));
    };
    if let Some(bad) = values.iter().find(|v| !(0.0..=1.0).contains(*v)) {
        return Err(Error::Usage(format!(
            "--cropwindow {a},{b},{c},{d}: {bad} is not a fraction of the image (0 to 1)"
        )));
    }
    let window = [a.min(b), a.max(b), c.min(d), c.max(d)];
    if window[0] == window[1] || window[2] == window[3] {
        return Err(Error::Usage(format!(
            "--cropwindow {a},{b},{c},{d} is empty (x0 x1 y0 y1: each pair must differ)"
        )));
    }
    Ok(window)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn expand(args: &[&str]) -> Result<Vec<String>, Error> {
        let expanded = expand_comma_lists(args.iter().map(OsString::from))?;
        Ok(expanded
            .into_iter()
            .map(|a| a.into_string().unwrap())
            .collect())
    }

    #[test]
    fn pbrt_v4_lists_become_four_arguments() {
        let four = ["rpbrt", "--pixelbounds", "0", "120", "0", "90", "s.pbrt"];
        assert_eq!(
            expand(&["rpbrt", "--pixelbounds", "0,120,0,90", "s.pbrt"]).unwrap(),
            four
        );
        assert_eq!(
            expand(&["rpbrt", "--pixelbounds=0,120,0,90", "s.pbrt"]).unwrap(),
            four
        );
        assert_eq!(expand(&four).unwrap(), four);
        assert_eq!(
            expand(&["rpbrt", "s.pbrt", "--cropwindow", "0, 0.5,0,.5"]).unwrap(),
            ["rpbrt", "s.pbrt", "--cropwindow", "0", "0.5", "0", ".5"]
        );
        // Only these flags, and nothing after `--`.
        let other = ["rpbrt", "--outfile", "a,b.exr", "--", "--cropwindow", "1,2"];
        assert_eq!(expand(&other).unwrap(), other);
    }

    #[test]
    fn lists_of_other_lengths_are_errors() {
        for args in [
            &["rpbrt", "--pixelbounds", "0,120,0", "s.pbrt"][..],
            &["rpbrt", "--cropwindow=0,1,0,1,0"],
            &["rpbrt", "--pixelbounds=5"],
        ] {
            let error = expand(args).unwrap_err().to_string();
            assert!(error.contains("takes four values"), "{error}");
        }
    }

    #[test]
    fn bounds_are_ordered_and_must_hold_pixels() {
        assert_eq!(pixel_bounds(&[0, 120, 0, 90]).unwrap(), [0, 120, 0, 90]);
        assert_eq!(pixel_bounds(&[120, 0, 90, 0]).unwrap(), [0, 120, 0, 90]);
        let error = pixel_bounds(&[5, 5, 0, 90]).unwrap_err().to_string();
        assert!(error.contains("holds no pixels"), "{error}");
        assert!(pixel_bounds(&[0, 1, 0]).is_err());
    }

    #[test]
    fn crop_windows_are_fractions() {
        assert_eq!(
            crop_window(&[0.5, 0.0, 0.0, 0.5]).unwrap(),
            [0.0, 0.5, 0.0, 0.5]
        );
        for bad in [
            [0.0, 1.5, 0.0, 1.0],
            [-0.1, 1.0, 0.0, 1.0],
            [0.0, f64::NAN, 0.0, 1.0],
        ] {
            let error = crop_window(&bad).unwrap_err().to_string();
            assert!(error.contains("is not a fraction"), "{error}");
        }
        let error = crop_window(&[0.25, 0.25, 0.0, 1.0])
            .unwrap_err()
            .to_string();
        assert!(error.contains("is empty"), "{error}");
    }
}
