use glam::DVec3;

/// A plane `normal . p + offset = 0`; the points with a non-negative signed distance are its
/// inside (the side that clipping keeps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// Unit normal, pointing to the inside.
    pub normal: DVec3,
    /// Offset: `-normal . q` for any point `q` on the plane.
    pub offset: f64,
}

impl Plane {
    /// The plane through `point` with (unit) inward `normal`.
    pub fn through_point(point: DVec3, normal: DVec3) -> Self {
        Self {
            normal,
            offset: -normal.dot(point),
        }
    }

    /// Signed distance of `p` (positive inside).
    #[inline]
    pub fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) + self.offset
    }

    /// The same plane with the inside and outside swapped.
    pub fn flipped(&self) -> Self {
        Self {
            normal: -self.normal,
            offset: -self.offset,
        }
    }
}
