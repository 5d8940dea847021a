//! Curve vertices put back in order along their chart sides.
//!
//! A vertex of a curve held on its chart side has one unknown, its share `s` of the way from
//! the curve's first node to its last. Nothing in the harmonic energy keeps a curve's shares
//! in order: where a node's chart angle is far from the surface's (a corner where the face
//! hardly turns, a T-vertex where it turns sharply), a solve can put a vertex behind its
//! neighbour or past the node, and the triangles between them fold (on bunny_28k's automatic
//! layout, 38 of the 50 flipped triangles touched such a vertex).
//!
//! The mend moves as little as it can: the shares in order nearest to the solve's own (an
//! isotonic regression), with a least gap between neighbours so no triangle collapses. The
//! vertices it moves are then held there and the system solved again (see
//! `ParamSession::finish`). An earlier mend held them at their share of the curve's length
//! instead; that moved the quads off the surface by up to 40 % more on some layouts.

/// The least gap kept between two neighbours of a curve put back in order, as a share of
/// the surface length between them over the curve's.
const LEAST_GAP: f64 = 0.2;

/// The shares in `s` (of the inner vertices of one curve, whose ends are at 0 and 1) if they
/// are out of order: the nearest ones in order in the least-squares sense, each at least
/// `LEAST_GAP` times its share `length` of the curve ahead of the one before it (`length`
/// has one entry per piece of the curve, `s.len() + 1`, and sums to 1). `None` if `s` is in
/// order already.
pub fn nearest_in_order(s: &[f64], length: &[f64]) -> Option<Vec<f64>> {
    // Each vertex, and the end at 1, at least its least gap ahead of the one before.
    let ahead = s.iter().chain([1.0].iter()).scan(0.0, |before, &x| Some(x - std::mem::replace(before, x)));
    if ahead.zip(length).all(|(gap, &l)| gap >= LEAST_GAP * l) {
        return None;
    }
    // With g_k the least gaps summed up to vertex k, u_k = s_k − g_k must only not decrease,
    // between 0 and 1 − (all the gaps): pool adjacent violators (PAVA), then clamp.
    let gaps: Vec<f64> = length.iter().scan(0.0, |sum, &l| {
        *sum += LEAST_GAP * l;
        Some(*sum)
    }).collect();
    let top = 1.0 - gaps.last().copied().unwrap_or(0.0);
    // Blocks of pooled vertices: (mean, count).
    let mut blocks: Vec<(f64, usize)> = Vec::with_capacity(s.len());
    for (x, g) in s.iter().zip(&gaps) {
        let mut block = (x - g, 1);
        while let Some(&(mean, count)) = blocks.last() {
            if mean < block.0 {
                break;
            }
            blocks.pop();
            let n = count + block.1;
            block = ((mean * count as f64 + block.0 * block.1 as f64) / n as f64, n);
        }
        blocks.push(block);
    }
    let u = blocks.iter().flat_map(|&(mean, count)| std::iter::repeat_n(mean.clamp(0.0, top), count));
    Some(u.zip(&gaps).map(|(u, g)| u + g).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_in_order_with_room_are_left_alone() {
        assert_eq!(nearest_in_order(&[0.25, 0.5, 0.75], &[0.25; 4]), None);
    }

    #[test]
    fn a_vertex_behind_its_neighbour_meets_it_halfway_with_the_least_gap_between() {
        let fixed = nearest_in_order(&[0.2, 0.6, 0.4, 0.8], &[0.2; 5]).unwrap();
        // 0.6 and 0.4 pool round their mean 0.5, LEAST_GAP * 0.2 apart.
        let gap = LEAST_GAP * 0.2;
        let want = [0.2, 0.5 - gap / 2.0, 0.5 + gap / 2.0, 0.8];
        for (a, b) in fixed.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{fixed:?}");
        }
    }

    #[test]
    fn vertices_past_the_end_are_brought_back_inside_in_order() {
        let length = [0.25; 4];
        let fixed = nearest_in_order(&[0.5, 1.2, 1.1], &length).unwrap();
        let mut before = 0.0;
        for (x, l) in fixed.iter().chain([1.0].iter()).zip(length) {
            assert!(x - before >= LEAST_GAP * l - 1e-12, "{fixed:?}");
            before = *x;
        }
        assert!((fixed[0] - 0.5).abs() < 1e-12, "the vertex in order stays: {fixed:?}");
    }
}
