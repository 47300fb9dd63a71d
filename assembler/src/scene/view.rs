//! simtrax `.view` (camera) and `.light` (point light) files.
//!
//! `.view`: 15 whitespace-separated numbers `eye(3) gaze(3) up(3) aperture left right bottom
//! top distance`. As in simtrax's `Camera.cc`, the second triple is a gaze *direction*, not a
//! look-at point. `.light`: the light position (three numbers), optionally followed by its
//! intensity: one number (white light of that intensity) or three (linear RGB). Without
//! one the intensity is 1 (simtrax's files have none).

use std::path::Path;

use trax_runtime::abi::Camera;

use super::{cross, normalize_or_zero, rescale_pow2, Bounds, PointLight, SceneError, Vec3};

/// A camera as written in a `.view` file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub eye: Vec3,
    /// Gaze direction (need not be normalized).
    pub gaze: Vec3,
    /// Up vector.
    pub up: Vec3,
    /// Lens aperture (0 = pinhole).
    pub aperture: f32,
    /// Image-plane window: left edge.
    pub left: f32,
    /// Image-plane window: right edge.
    pub right: f32,
    /// Image-plane window: bottom edge.
    pub bottom: f32,
    /// Image-plane window: top edge.
    pub top: f32,
    /// Distance from the eye to the image plane.
    pub distance: f32,
}

impl View {
    /// A camera on the +z side of `b` looking down -z with +y up, framing the whole box.
    ///
    /// Computed in f64, so it is finite for every box of finite f32 coordinates whose eye
    /// position (2.5 half-diagonals above the centre) is itself a finite f32. A box of zero
    /// size is framed as if it were a tiny fraction (2^-20) of its distance from the origin
    /// across, so the framing is relative at every scale (the smallest positive f32 for
    /// a box at the origin).
    pub fn framing(b: &Bounds) -> View {
        let c = b.center();
        let mut r = 0.5 * b.diagonal_f64();
        if r == 0.0 {
            r = (b.magnitude() as f64 * f64::powi(2.0, -20)).max(f32::from_bits(1) as f64);
        }
        View {
            eye: [c[0], c[1], (c[2] as f64 + 2.5 * r) as f32],
            gaze: [0.0, 0.0, -1.0],
            up: [0.0, 1.0, 0.0],
            aperture: 0.0,
            left: -1.0,
            right: 1.0,
            bottom: -1.0,
            top: 1.0,
            distance: 2.0,
        }
    }

    /// The camera basis stored in memory (see [`Camera`]): `w` = unit gaze,
    /// `u` = unit(gaze × up), `v` = u × w.
    pub fn camera(&self) -> Result<Camera, SceneError> {
        let all = self
            .eye
            .iter()
            .chain(&self.gaze)
            .chain(&self.up)
            .chain(&[
                self.aperture,
                self.left,
                self.right,
                self.bottom,
                self.top,
                self.distance,
            ])
            .all(|c| c.is_finite());
        if !all {
            return Err(SceneError::BadCamera(
                "camera has a non-finite number".into(),
            ));
        }
        let w = normalize_or_zero(self.gaze);
        if w == [0.0; 3] {
            return Err(SceneError::BadCamera(
                "camera gaze direction is zero".into(),
            ));
        }
        // Gaze and up may be of any finite size: rescaled first (exactly, by powers of two),
        // since an f32 cross product of vectors longer than about 1e19 overflows.
        let u = normalize_or_zero(cross(rescale_pow2(self.gaze), rescale_pow2(self.up)));
        if u == [0.0; 3] {
            return Err(SceneError::BadCamera(
                "camera up vector is zero or parallel to the gaze direction".into(),
            ));
        }
        if self.distance <= 0.0 {
            return Err(SceneError::BadCamera(format!(
                "camera image-plane distance must be positive, got {}",
                self.distance
            )));
        }
        let v = cross(u, w);
        Ok(Camera {
            eye: self.eye,
            u,
            v,
            w,
            left: self.left,
            right: self.right,
            bottom: self.bottom,
            top: self.top,
            distance: self.distance,
            aperture: self.aperture,
        })
    }
}

/// Reads a file's text, naming it in errors.
fn read_text(path: &Path) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The numbers of a `.view`/`.light` text, as many as one of `counts` (ascending; `path`
/// names it in errors), each with its line.
fn numbers_of(
    path: &Path,
    text: &str,
    counts: &[usize],
    what: &str,
) -> Result<Vec<(f32, usize)>, SceneError> {
    let want = counts.last().copied().unwrap_or(0);
    let allowed = match counts {
        [n] => format!("exactly {n}"),
        [rest @ .., last] => format!(
            "{} or {last}",
            rest.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
        [] => "no".into(),
    };
    let mut nums = Vec::with_capacity(want);
    let mut last_line = 1;
    for (i, line) in text.lines().enumerate() {
        for tok in line.split_whitespace() {
            last_line = i + 1;
            let syntax = |message: String| SceneError::Syntax {
                path: path.to_path_buf(),
                line: i + 1,
                message,
            };
            if nums.len() == want {
                return Err(syntax(format!(
                    "unexpected `{tok}`: a {what} file has {allowed} numbers"
                )));
            }
            let v: f32 = tok
                .parse()
                .map_err(|_| syntax(format!("expected a number, found `{tok}`")))?;
            if !v.is_finite() {
                return Err(syntax(format!("expected a finite number, found `{tok}`")));
            }
            nums.push((v, i + 1));
        }
    }
    if !counts.contains(&nums.len()) {
        return Err(SceneError::Syntax {
            path: path.to_path_buf(),
            line: last_line,
            message: format!(
                "a {what} file needs {allowed} numbers, found {}",
                nums.len()
            ),
        });
    }
    Ok(nums)
}

/// What a `.view` file holds, for errors.
const VIEW_WHAT: &str = ".view (eye, gaze, up, aperture, left, right, bottom, top, distance)";

/// Parses a simtrax `.view` file.
pub fn parse_view(path: &Path) -> Result<View, SceneError> {
    parse_view_str(path, &read_text(path)?)
}

/// Parses the text of a simtrax `.view` file (`path` names it in errors).
pub fn parse_view_str(path: &Path, text: &str) -> Result<View, SceneError> {
    view_from(path, numbers_of(path, text, &[15], VIEW_WHAT)?)
}

/// What a `.light` file holds, for errors.
const LIGHT_WHAT: &str = ".light (position, then optionally an intensity or an RGB intensity)";

/// Parses the text of a `.light` file (`path` names it in errors): a position, then
/// optionally one intensity or three (linear RGB, each at least 0); intensity 1 without.
pub fn parse_light_str(path: &Path, text: &str) -> Result<PointLight, SceneError> {
    let numbers = numbers_of(path, text, &[3, 4, 6], LIGHT_WHAT)?;
    let n: Vec<f32> = numbers.iter().map(|x| x.0).collect();
    let color = match n.len() {
        4 => [n[3]; 3],
        6 => [n[3], n[4], n[5]],
        _ => [1.0; 3],
    };
    if color.iter().any(|c| *c < 0.0) {
        return Err(SceneError::Syntax {
            path: path.to_path_buf(),
            line: numbers.last().map_or(1, |x| x.1),
            message: format!("a light's intensity must be at least 0, found {color:?}"),
        });
    }
    Ok(PointLight {
        position: [n[0], n[1], n[2]],
        color,
    })
}

fn view_from(path: &Path, numbers: Vec<(f32, usize)>) -> Result<View, SceneError> {
    let n: Vec<f32> = numbers.iter().map(|x| x.0).collect();
    // An empty image window (left = right or bottom = top) makes every pixel's ray the same.
    for (lo, hi, what) in [(10, 11, "left = right"), (12, 13, "bottom = top")] {
        if n[lo] == n[hi] {
            return Err(SceneError::Syntax {
                path: path.to_path_buf(),
                line: numbers[hi].1,
                message: format!(
                    "the image window has zero size ({what} = {}): every pixel would be the same",
                    n[hi]
                ),
            });
        }
    }
    let view = View {
        eye: [n[0], n[1], n[2]],
        gaze: [n[3], n[4], n[5]],
        up: [n[6], n[7], n[8]],
        aperture: n[9],
        left: n[10],
        right: n[11],
        bottom: n[12],
        top: n[13],
        distance: n[14],
    };
    view.camera()
        .map_err(|e| SceneError::BadCamera(format!("{}: {e}", path.display())))?;
    Ok(view)
}

/// Parses a `.light` file (one point light: [`parse_light_str`]).
pub fn parse_light(path: &Path) -> Result<PointLight, SceneError> {
    parse_light_str(path, &read_text(path)?)
}
