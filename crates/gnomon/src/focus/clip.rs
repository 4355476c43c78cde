//! Unit cube clipping's rule: a focused map's region from the receivers' and the casters'
//! extents.

use glam::DVec2;

use crate::light_space::Extents;

/// Unit cube clipping (see the module documentation): the region a focused map covers, from
/// the visible receivers' and the relevant casters' extents. `body`, B's extents when B is
/// usable, raises the near plane to B's nearest point: caster points nearer to the light lie
/// outside B and can shadow nothing visible. `None` when no caster is relevant.
pub(crate) fn unit_cube_clip(
    receivers: &Extents,
    casters: &Extents,
    body: Option<&Extents>,
) -> Option<Extents> {
    if casters.is_empty() || receivers.is_empty() {
        return None;
    }
    let mut near = casters.min.z;
    if let Some(b) = body {
        near = near.max(b.min.z);
    }
    let far = receivers.max.z;
    let (lo, hi) = clipped_rectangle(receivers, casters);
    Some(Extents {
        min: lo.extend(near.min(far)),
        max: hi.extend(far),
    })
}

/// Unit cube clipping's x and y: the receivers' and the casters' rectangles intersected.
/// Casters that only touch the receivers' rectangle (within the culling slack) leave an
/// inverted interval: it collapses to its middle, and padding gives it a size.
pub(crate) fn clipped_rectangle(receivers: &Extents, casters: &Extents) -> (DVec2, DVec2) {
    let lo = receivers.min.max(casters.min).truncate();
    let hi = receivers.max.min(casters.max).truncate();
    let mid = 0.5 * (lo + hi);
    (lo.min(mid), hi.max(mid))
}
