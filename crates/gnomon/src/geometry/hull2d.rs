use glam::DVec2;

/// The convex hull of 2D points (Andrew's monotone chain), as indices into `points` in
/// counter-clockwise order, without collinear points and without vertices that coincide to
/// within a trillionth of the points' extent. Such a pair would make an edge with no
/// meaningful direction: points that project to the same spot differ by round-off. Fewer
/// than three indices come back when the points are collinear or coincide.
pub fn convex_hull_2d(points: &[DVec2]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (points[a], points[b]);
        p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y))
    });
    order.dedup_by(|a, b| points[*a] == points[*b]);
    if order.len() < 3 {
        return order;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<usize> = Vec::with_capacity(order.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        // The lower chain left to right, then the upper one right to left.
        for k in 0..order.len() {
            let i = if pass == 0 {
                order[k]
            } else {
                order[order.len() - 1 - k]
            };
            while hull.len() >= start + 2
                && cross(
                    points[hull[hull.len() - 2]],
                    points[hull[hull.len() - 1]],
                    points[i],
                ) <= 0.0
            {
                hull.pop();
            }
            hull.push(i);
        }
        hull.pop();
    }
    // Vertices that coincide up to round-off: keep one of each run (cyclically).
    let extent = order
        .iter()
        .map(|&i| points[i].abs().max_element())
        .fold(0.0, f64::max);
    let eps = 1e-12 * extent;
    let mut merged: Vec<usize> = Vec::with_capacity(hull.len());
    for &i in &hull {
        if merged
            .last()
            .is_none_or(|&j| points[j].distance(points[i]) > eps)
        {
            merged.push(i);
        }
    }
    while merged.len() > 1 && points[merged[0]].distance(points[*merged.last().unwrap()]) <= eps {
        merged.pop();
    }
    merged
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_that_coincide_up_to_round_off_make_one_vertex() {
        // Two corners 1e-15 apart (as frustum corners projected along a light parallel to a
        // face come out): one hull vertex, so that no edge has a round-off direction.
        let pts = [
            DVec2::new(-7.296315797578819, -2.521682388810756),
            DVec2::new(-7.296315797578818, -2.5216823888107545),
            DVec2::new(10.528159257008419, -2.5216823888107553),
            DVec2::new(1.6166875067865885, 16.04995008620322),
            DVec2::new(1.6151559526430095, 16.04995008620322),
        ];
        let hull = convex_hull_2d(&pts);
        assert_eq!(hull.len(), 4, "{hull:?}");
        for (k, &i) in hull.iter().enumerate() {
            let j = hull[(k + 1) % hull.len()];
            assert!(pts[i].distance(pts[j]) > 1e-6, "edge {i} -> {j}");
        }
    }

    #[test]
    fn square_with_interior_and_collinear_points() {
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.5, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(0.5, 0.5),
            DVec2::new(1.0, 1.0),
        ];
        let hull = convex_hull_2d(&pts);
        assert_eq!(hull.len(), 4);
        let area: f64 = (0..4)
            .map(|i| pts[hull[i]].perp_dot(pts[hull[(i + 1) % 4]]))
            .sum::<f64>()
            / 2.0;
        assert!(
            (area - 1.0).abs() < 1e-12,
            "counter-clockwise unit square, got area {area}"
        );
    }

    #[test]
    fn collinear_points_give_a_segment() {
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(2.0, 2.0),
        ];
        assert!(convex_hull_2d(&pts).len() < 3);
    }
}
