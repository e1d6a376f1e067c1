//! The signed distance of two placed shapes whose Minkowski difference has few points (a
//! link's circle or capsule against another, or against the base's box), hulled on the stack.

use crate::scalar::Scalar;

/// Minkowski differences of at most this many points are hulled on the stack
/// ([`signed_distance`]): a box against a capsule has 8.
pub(super) const SMALL: usize = 8;

/// `sd(0, hull(a - b))` for at most [`SMALL`] points `a - b`: the same steps as [`super::hull`] (the
/// same stable order, exact repeats dropped, Andrew's chains) on indices kept on the stack, and
/// [`super::origin_signed_distance`] on the hull's points, so the same value bit for bit without an
/// allocation (a link's circles against the base's box, at every row point of the planner).
pub(super) fn signed_distance<D: Scalar>(a: &[[D; 2]], b: &[[D; 2]]) -> D {
    let zero = D::from(0.0);
    let mut diff = [[zero; 2]; SMALL];
    let mut re = [[0.0; 2]; SMALL];
    let mut n = 0;
    for p in a {
        for q in b {
            diff[n] = [p[0] - q[0], p[1] - q[1]];
            re[n] = [diff[n][0].re(), diff[n][1].re()];
            n += 1;
        }
    }
    let mut order = [0usize; SMALL];
    for (k, o) in order.iter_mut().enumerate() {
        *o = k;
    }
    let order = &mut order[..n];
    order.sort_by(|&i, &j| re[i][0].total_cmp(&re[j][0]).then(re[i][1].total_cmp(&re[j][1])));
    // Exact repeats only, each against the last point kept (as `dedup_by`).
    let mut kept = 0;
    for k in 0..n {
        let i = order[k];
        let same = kept > 0 && {
            let j = order[kept - 1];
            re[i][0].total_cmp(&re[j][0]).is_eq() && re[i][1].total_cmp(&re[j][1]).is_eq()
        };
        if !same {
            order[kept] = i;
            kept += 1;
        }
    }
    let order = &order[..kept];
    let at = |k: &[usize]| {
        let mut points = [[zero; 2]; 2 * SMALL];
        for (p, &i) in points.iter_mut().zip(k) {
            *p = diff[i];
        }
        super::origin_signed_distance(&points[..k.len()])
    };
    if order.len() < 3 {
        return at(order);
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    // The lower chain then the upper one, each without its last point, into `out`.
    let mut out = [0usize; 2 * SMALL];
    let mut len = 0;
    for reversed in [false, true] {
        let start = len;
        for k in 0..order.len() {
            let i = if reversed { order[order.len() - 1 - k] } else { order[k] };
            while len >= start + 2 && cross(re[out[len - 2]], re[out[len - 1]], re[i]) <= 0.0 {
                len -= 1;
            }
            out[len] = i;
            len += 1;
        }
        len -= 1;
    }
    if len < 3 {
        // All points in a line: the two extremes.
        return at(&[order[0], order[order.len() - 1]]);
    }
    at(&out[..len])
}
