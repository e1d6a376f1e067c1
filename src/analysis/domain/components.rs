//! Connected-component labelling of the cells on the torus and the trigonometric tables of the
//! cell centres (the discretisation of Sec. 6, item 3's domains; see the parent module's docs).

use super::NONE;

/// Connected components of the cells with equal non-zero `keys` on the `n x n` torus
/// (4-neighbours, wrap-around on both axes), by flood fill in row-major order.
///
/// Returns the label of each cell (`NONE` where the key is 0) and, per component, its number of
/// cells and first cell index; components are numbered by decreasing area, ties by first cell.
pub(super) fn label_components(n: usize, keys: &[u8]) -> (Vec<u32>, Vec<(usize, usize)>) {
    let mut labels = vec![NONE; n * n];
    let mut found: Vec<(usize, usize)> = Vec::new(); // (cells, first index)
    let mut stack: Vec<usize> = Vec::new();
    for start in 0..n * n {
        if keys[start] == 0 || labels[start] != NONE {
            continue;
        }
        let label = found.len() as u32;
        let k = keys[start];
        labels[start] = label;
        stack.push(start);
        let mut cells = 0;
        while let Some(c) = stack.pop() {
            cells += 1;
            let (i1, i2) = (c % n, c / n);
            let row = i2 * n;
            let neighbours = [
                row + if i1 + 1 == n { 0 } else { i1 + 1 },
                row + if i1 == 0 { n - 1 } else { i1 - 1 },
                if i2 + 1 == n { i1 } else { c + n },
                if i2 == 0 { (n - 1) * n + i1 } else { c - n },
            ];
            for nb in neighbours {
                if keys[nb] == k && labels[nb] == NONE {
                    labels[nb] = label;
                    stack.push(nb);
                }
            }
        }
        found.push((cells, start));
    }
    // Renumber by decreasing area (stable: ties keep row-major order of first cells).
    let mut order: Vec<usize> = (0..found.len()).collect();
    order.sort_by(|&x, &y| found[y].0.cmp(&found[x].0));
    let mut rank = vec![0u32; found.len()];
    for (new, &old) in order.iter().enumerate() {
        rank[old] = new as u32;
    }
    for l in labels.iter_mut().filter(|l| **l != NONE) {
        *l = rank[*l as usize];
    }
    (labels, order.into_iter().map(|old| found[old]).collect())
}

/// `sin` and `cos` of `(k + offset) h` for `k` in `0..n`, `h = 2 pi / n`.
pub(super) fn trig_table(n: usize, offset: f64) -> Vec<(f64, f64)> {
    let h = std::f64::consts::TAU / n as f64;
    (0..n).map(|k| ((k as f64 + offset) * h).sin_cos()).collect()
}
