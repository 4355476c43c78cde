//! The subtrees a caster walk puts off, opened the farthest-reaching first.
//!
//! A caster walk ([`crate::focus::walk_casters`], the view warp's tree walk) gathers the
//! extents of the casters over the receivers. A subtree no nearer than what is gathered can
//! add only in x and y; early in the walk the extents are small, so such a subtree is put off
//! rather than opened, and opened at the end only where the extents do not hold its image by
//! then. Which put-off subtree is opened first decides how many are opened: the one whose
//! image reaches farthest beyond the gathered extents (along x or y, as a share of the
//! receivers' width or height) is most likely to hold the caster that settles that side, after
//! which the others on that side are held and dropped unopened. A subtree opened from the
//! queue puts off its own children in turn. Before, each put-off subtree was opened in the
//! order it was put off, down to its leaves, before the next: in the benches' city of 10^4
//! boxes, four LiSPSM cascades opened 935 nodes where 132 had to be (those whose image the
//! final extents do not hold); in this order, 321.
//!
//! The order changes only which subtrees are opened, never the extents: a subtree is dropped
//! only where the extents hold its image, so its boxes add nothing.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::collections::binary_heap::PeekMut;

use glam::DVec2;

use crate::light_space::Extents;

/// Put-off subtrees (`T`: what the walk needs to open one) with their images, in a queue
/// ordered by how far each image reaches beyond the extents gathered when it was last looked
/// at. The reach only shrinks as the extents grow, so a subtree popped with an old reach is
/// looked at again and put back where another reaches farther now.
pub(crate) struct PutOff<T> {
    items: Vec<(T, Extents)>,
    /// How many of `items` are in `queue` (those after were put off since the last pop).
    queued: usize,
    queue: BinaryHeap<Reach>,
    /// 1 / the receivers' width and height: reaches along x and y as shares of them.
    per_unit: DVec2,
}

/// How far item `index`'s image reaches beyond the gathered extents.
#[derive(Debug, Clone, Copy)]
struct Reach {
    reach: f64,
    index: u32,
}

impl PartialEq for Reach {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Reach {}

impl PartialOrd for Reach {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Reach {
    /// Farther first; of equal reaches the later put off (a smaller subtree, as a walk goes
    /// deeper), as a depth-first walk would.
    fn cmp(&self, other: &Self) -> Ordering {
        self.reach
            .total_cmp(&other.reach)
            .then(self.index.cmp(&other.index))
    }
}

/// How far `image` reaches beyond `gathered` along x or y (the farther, in shares of the
/// receivers' width and height, `per_unit` their inverses; at most 0 where `gathered` holds it
/// in both).
#[inline]
fn reach(image: &Extents, gathered: &Extents, per_unit: DVec2) -> f64 {
    let beyond = (image.max - gathered.max)
        .truncate()
        .max((gathered.min - image.min).truncate());
    (beyond * per_unit).max_element()
}

impl<T: Copy> PutOff<T> {
    /// An empty queue for a walk over receivers whose extents (x and y) are `over`.
    pub fn new(over: &Extents) -> Self {
        let size = (over.max - over.min).truncate();
        Self {
            items: Vec::with_capacity(16),
            queued: 0,
            queue: BinaryHeap::new(),
            per_unit: DVec2::ONE / size.max(DVec2::splat(f64::MIN_POSITIVE)),
        }
    }

    /// Puts off `item`, whose subtree's image is `image`. It is queued at the next
    /// [`PutOff::pop`] (by then the extents may hold it, as they hold most).
    pub fn push(&mut self, item: T, image: Extents) {
        self.items.push((item, image));
    }

    /// The put-off subtree to open next: of those whose image `gathered` does not hold, the
    /// one that reaches farthest beyond it. Those it holds are dropped (they add nothing).
    pub fn pop(&mut self, gathered: &Extents) -> Option<T> {
        let per_unit = self.per_unit;
        for index in self.queued..self.items.len() {
            let image = &self.items[index].1;
            if !gathered.contains(image) {
                self.queue.push(Reach {
                    reach: reach(image, gathered, per_unit),
                    index: index as u32,
                });
            }
        }
        self.queued = self.items.len();
        while let Some(mut top) = self.queue.peek_mut() {
            let (item, image) = self.items[top.index as usize];
            if gathered.contains(&image) {
                PeekMut::pop(top);
                continue;
            }
            // Where its reach has shrunk, it goes back in at its new place (on the drop of
            // `top`), and is taken if it is still first.
            let now = reach(&image, gathered, per_unit);
            if now < top.reach {
                top.reach = now;
                continue;
            }
            PeekMut::pop(top);
            return Some(item);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    fn ext(min: [f64; 2], max: [f64; 2]) -> Extents {
        Extents {
            min: DVec3::new(min[0], min[1], 0.0),
            max: DVec3::new(max[0], max[1], 1.0),
        }
    }

    #[test]
    fn the_farthest_reaching_is_opened_first_and_held_ones_are_dropped() {
        let over = ext([0.0, 0.0], [10.0, 100.0]);
        let mut gathered = ext([4.0, 40.0], [6.0, 60.0]);
        let mut put_off = PutOff::new(&over);
        // Reaches: 0.1 (x, 1 of 10), 0.3 (y, 30 of 100), 0.2 (x), and one held.
        put_off.push('a', ext([3.0, 45.0], [5.0, 55.0]));
        put_off.push('b', ext([5.0, 50.0], [6.0, 90.0]));
        put_off.push('c', ext([5.0, 50.0], [8.0, 55.0]));
        put_off.push('d', ext([4.5, 45.0], [5.5, 55.0]));
        assert_eq!(put_off.pop(&gathered), Some('b'));
        // The extents grow to hold c's image: c is dropped, a (reach 0.1) comes next.
        gathered.max.x = 8.0;
        assert_eq!(put_off.pop(&gathered), Some('a'));
        assert_eq!(put_off.pop(&gathered), None);
    }

    #[test]
    fn an_old_reach_is_looked_at_again() {
        let over = ext([0.0, 0.0], [10.0, 10.0]);
        let mut gathered = ext([4.0, 4.0], [6.0, 6.0]);
        let mut put_off = PutOff::new(&over);
        put_off.push('a', ext([4.0, 4.0], [9.0, 6.0])); // reach 0.3
        put_off.push('b', ext([4.0, 2.0], [6.0, 6.0])); // reach 0.2
        put_off.push('c', ext([4.0, 4.0], [7.5, 6.0])); // reach 0.15
        put_off.push('d', ext([4.0, 4.0], [6.0, 7.0])); // reach 0.1
        assert_eq!(put_off.pop(&gathered), Some('a'));
        // a's subtree grows the extents to 7 in x: c reaches 0.05 now, behind d.
        gathered.max.x = 7.0;
        assert_eq!(put_off.pop(&gathered), Some('b'));
        assert_eq!(put_off.pop(&gathered), Some('d'));
        assert_eq!(put_off.pop(&gathered), Some('c'));
        // Put off after a pop: queued at the next, and dropped there if held.
        put_off.push('e', ext([4.5, 4.5], [5.0, 5.0]));
        put_off.push('f', ext([4.5, 4.5], [5.0, 8.0]));
        assert_eq!(put_off.pop(&gathered), Some('f'));
        assert_eq!(put_off.pop(&gathered), None);
    }
}
