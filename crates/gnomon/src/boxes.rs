//! Axis-aligned boxes, and boxes side by side for the walks through their hierarchies.

use glam::DVec3;

use crate::error::{SetupError, check_vec};

/// An axis-aligned box in world space, `min <= max` on every axis.
///
/// A box may be flat (zero size along one or two axes: a ground quad, a wall) but not a
/// point. Construct with [`Aabb::new`], which validates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    min: DVec3,
    max: DVec3,
}

impl Aabb {
    /// A box from its minimum and maximum corners.
    ///
    /// Errors: non-finite or out-of-range coordinates, `min > max` on any axis
    /// ([`SetupError::InvertedBox`]), or `min == max` (a point, [`SetupError::EmptyBox`]).
    pub fn new(min: DVec3, max: DVec3) -> Result<Self, SetupError> {
        check_vec("box corner", min)?;
        check_vec("box corner", max)?;
        if min.cmpgt(max).any() {
            return Err(SetupError::InvertedBox { min, max });
        }
        if min == max {
            return Err(SetupError::EmptyBox { at: min });
        }
        Ok(Self { min, max })
    }

    /// A box from its centre and half extents (each `>= 0`, not all zero).
    pub fn from_center_half_extents(
        center: DVec3,
        half_extents: DVec3,
    ) -> Result<Self, SetupError> {
        check_vec("box centre", center)?;
        check_vec("box half extents", half_extents)?;
        Self::new(center - half_extents, center + half_extents)
    }

    /// The minimum corner.
    pub fn min(&self) -> DVec3 {
        self.min
    }

    /// The maximum corner.
    pub fn max(&self) -> DVec3 {
        self.max
    }

    /// The centre.
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the size along each axis.
    pub fn half_extents(&self) -> DVec3 {
        0.5 * (self.max - self.min)
    }

    /// The length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).length()
    }

    /// A box from corners known to be valid (a tree node's, made from valid boxes).
    pub(crate) fn from_min_max_unchecked(min: DVec3, max: DVec3) -> Aabb {
        Aabb { min, max }
    }

    /// The eight corners; bit 0 of the index selects max x, bit 1 max y, bit 2 max z.
    pub fn corners(&self) -> [DVec3; 8] {
        std::array::from_fn(|i| {
            DVec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Whether `other` lies inside this box.
    pub fn contains_box(&self, other: &Aabb) -> bool {
        self.min.cmple(other.min).all() && self.max.cmpge(other.max).all()
    }

    /// Whether `p` lies inside this box grown by `tolerance` on every side.
    pub fn contains_point(&self, p: DVec3, tolerance: f64) -> bool {
        (self.min - tolerance).cmple(p).all() && (self.max + tolerance).cmpge(p).all()
    }

    /// The box grown by `margin` on every side (`margin >= 0`).
    pub(crate) fn grown(&self, margin: DVec3) -> Aabb {
        Aabb {
            min: self.min - margin,
            max: self.max + margin,
        }
    }
}

/// Boxes as centre and half extents, side by side: a walk through a hierarchy reads a box's
/// six numbers together, from one place. Built once with the scene bounds.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct BoxArrays {
    /// Each box's centre and half extents.
    boxes: Vec<[DVec3; 2]>,
}

impl BoxArrays {
    /// How many boxes.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    /// Box `i`'s centre.
    #[inline]
    pub fn center_of(&self, i: usize) -> DVec3 {
        self.boxes[i][0]
    }

    /// Box `i`'s half extents.
    #[inline]
    pub fn half_of(&self, i: usize) -> DVec3 {
        self.boxes[i][1]
    }

    /// Box `i`'s centre and half extents.
    #[inline]
    pub fn center_half(&self, i: usize) -> (DVec3, DVec3) {
        let [c, h] = self.boxes[i];
        (c, h)
    }

    /// Appends a box by its centre and half extents.
    pub(crate) fn push(&mut self, center: DVec3, half: DVec3) {
        self.boxes.push([center, half]);
    }

    /// Sets box `i`'s centre and half extents.
    pub(crate) fn set(&mut self, i: usize, center: DVec3, half: DVec3) {
        self.boxes[i] = [center, half];
    }

    pub(crate) fn new(boxes: &[Aabb]) -> Self {
        Self {
            boxes: boxes
                .iter()
                .map(|b| [b.center(), b.half_extents()])
                .collect(),
        }
    }
}
