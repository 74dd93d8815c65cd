//! Cameras: explicit (eye, target, up, projection), the `--view` presets, automatic framing
//! from the scene's bounding sphere, and the projection of points to the image.

use glam::DVec3;

use crate::InspectError;

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole perspective with this vertical field of view in degrees (in `(0, 180)`).
    Perspective {
        /// Vertical field of view, degrees.
        fov_y_degrees: f64,
    },
    /// Parallel projection; the image shows `2 * half_height` world units vertically.
    Orthographic {
        /// Half the world-space height of the view.
        half_height: f64,
    },
}

/// An explicit camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Centre of projection (for orthographic: a point on the view axis in front of the scene).
    pub eye: DVec3,
    /// The point looked at (the image centre).
    pub target: DVec3,
    /// Up direction (need not be orthogonal to the view direction, must not be parallel).
    pub up: DVec3,
    /// Projection.
    pub projection: Projection,
}

/// A view of the scene: a preset framed automatically from the bounding box, or a camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum View {
    /// Looking along −z (from +z), y up.
    Front,
    /// Looking along −x (from +x), y up.
    Side,
    /// Looking along −y (from +y), −z up.
    Top,
    /// From the (1, 1, 1) octant, y up.
    Iso,
    /// An explicit camera.
    Camera(Camera),
}

impl View {
    /// Parses `front`, `side`, `top` or `iso`.
    ///
    /// # Errors
    /// [`InspectError::InvalidOption`] naming the unknown view.
    pub fn parse(name: &str) -> Result<View, InspectError> {
        match name.trim().to_ascii_lowercase().as_str() {
            "front" => Ok(View::Front),
            "side" => Ok(View::Side),
            "top" => Ok(View::Top),
            "iso" => Ok(View::Iso),
            other => Err(InspectError::InvalidOption(format!(
                "unknown view `{other}` (expected front, side, top or iso)"
            ))),
        }
    }

    /// The camera of this view for a scene with the given bounding sphere, image aspect
    /// (width / height) and vertical field of view for the presets.
    pub(crate) fn camera(self, centre: DVec3, radius: f64, aspect: f64, fov_y: f64) -> Camera {
        let (dir, up) = match self {
            View::Camera(c) => return c,
            View::Front => (DVec3::Z, DVec3::Y),
            View::Side => (DVec3::X, DVec3::Y),
            View::Top => (DVec3::Y, DVec3::NEG_Z),
            View::Iso => (DVec3::ONE.normalize(), DVec3::Y),
        };
        // The bounding sphere fits in the narrower of the two half-angles; 5 % margin.
        let half_v = (fov_y.to_radians() / 2.0).clamp(1e-3, 1.5);
        let half_h = (aspect * half_v.tan()).atan();
        let half = half_v.min(half_h);
        let radius = radius.max(f64::MIN_POSITIVE);
        let distance = 1.05 * radius / half.sin();
        Camera {
            eye: centre + dir * distance,
            target: centre,
            up,
            projection: Projection::Perspective {
                fov_y_degrees: fov_y,
            },
        }
    }
}

/// A camera set up for one image cell: orthonormal basis and the screen mapping.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    pub eye: DVec3,
    /// Unit view direction.
    pub forward: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub width: f64,
    pub height: f64,
    /// Pixels per unit of (x/d, y/d) for perspective, per world unit for orthographic.
    pub scale: f64,
    pub perspective: bool,
    /// Least depth drawn (perspective): points closer than this are not projected.
    pub near: f64,
}

/// A projected point: pixel coordinates (x right, y down), `q` (affine in screen space and
/// larger for closer points: 1/depth for perspective, −depth for orthographic) and whether it
/// is in front of the near plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ScreenPoint {
    pub x: f32,
    pub y: f32,
    pub q: f32,
    pub visible: bool,
}

impl Frame {
    /// # Errors
    /// A degenerate camera (eye = target, up parallel to the view, bad field of view).
    pub fn new(c: &Camera, width: u32, height: u32, near: f64) -> Result<Frame, InspectError> {
        let bad = |m: &str| Err(InspectError::InvalidOption(format!("camera: {m}")));
        let view = c.target - c.eye;
        if view.length() <= 0.0 || !view.is_finite() {
            return bad("eye and target must be distinct finite points");
        }
        // A finite difference whose length overflows (an eye at 1e308) would normalise to
        // zero and be reported as an up parallel to the view.
        if !view.length().is_finite() {
            return bad("eye and target are too far apart (their distance overflows)");
        }
        let forward = view.normalize();
        let right = forward.cross(c.up);
        // `right` is NaN for a non-finite up; `is_finite` catches that too.
        if right.length() <= 1e-9 * c.up.length() || !right.is_finite() {
            return bad("up must not be parallel to the view direction");
        }
        let right = right.normalize();
        let up = right.cross(forward);
        let (w, h) = (f64::from(width), f64::from(height));
        let (scale, perspective) = match c.projection {
            Projection::Perspective { fov_y_degrees: f } => {
                if !(f > 0.0 && f < 180.0) {
                    return bad("the field of view must be in (0, 180) degrees");
                }
                (h / 2.0 / (f.to_radians() / 2.0).tan(), true)
            }
            Projection::Orthographic { half_height: s } => {
                if !(s > 0.0 && s.is_finite()) {
                    return bad("the orthographic half height must be positive");
                }
                (h / 2.0 / s, false)
            }
        };
        Ok(Frame {
            eye: c.eye,
            forward,
            right,
            up,
            width: w,
            height: h,
            scale,
            perspective,
            near,
        })
    }

    /// Depth along the view direction from `q` (see [`ScreenPoint`]).
    pub fn depth_of_q(&self, q: f32) -> f32 {
        if self.perspective { 1.0 / q } else { -q }
    }

    /// Projects a world point. The transform is done in f64; the result is rounded to f32,
    /// whose 24-bit mantissa resolves 1/1000 of a pixel for images up to 16k pixels, far below
    /// the sample spacing.
    pub fn project(&self, p: DVec3) -> ScreenPoint {
        let rel = p - self.eye;
        let (xc, yc, d) = (rel.dot(self.right), rel.dot(self.up), rel.dot(self.forward));
        if self.perspective {
            if d.is_nan() || d <= self.near {
                return ScreenPoint {
                    x: 0.0,
                    y: 0.0,
                    q: 0.0,
                    visible: false,
                };
            }
            ScreenPoint {
                x: (self.width / 2.0 + self.scale * xc / d) as f32,
                y: (self.height / 2.0 - self.scale * yc / d) as f32,
                q: (1.0 / d) as f32,
                visible: true,
            }
        } else {
            ScreenPoint {
                x: (self.width / 2.0 + self.scale * xc) as f32,
                y: (self.height / 2.0 - self.scale * yc) as f32,
                q: (-d) as f32,
                visible: true,
            }
        }
    }

    /// Unit world direction of the viewing ray through pixel coordinates (x, y).
    pub fn ray_direction(&self, x: f64, y: f64) -> DVec3 {
        if !self.perspective {
            return self.forward;
        }
        let dx = (x - self.width / 2.0) / self.scale;
        let dy = -(y - self.height / 2.0) / self.scale;
        (self.forward + dx * self.right + dy * self.up).normalize()
    }

    /// A direction given in camera coordinates (x right, y up, z towards the viewer) in world
    /// coordinates.
    pub fn camera_to_world(&self, v: DVec3) -> DVec3 {
        v.x * self.right + v.y * self.up - v.z * self.forward
    }
}
