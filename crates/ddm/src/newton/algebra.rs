//! Small vector and index algebra of the Newton method.

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(super) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// The (row, column, value) entries sorted by position, duplicates summed in their order.
pub(super) fn merge(mut entries: Vec<(usize, usize, f64)>) -> Vec<(usize, usize, f64)> {
    entries.sort_by_key(|e| (e.0, e.1));
    let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(entries.len());
    for (a, b, v) in entries {
        match merged.last_mut() {
            Some(last) if (last.0, last.1) == (a, b) => last.2 += v,
            _ => merged.push((a, b, v)),
        }
    }
    merged
}

/// One point per kernel vector where the vectors restricted to these points are regular:
/// Gaussian elimination with complete pivoting on the columns of `z`.
pub(super) fn pin_points(z: &[Vec<f64>]) -> Vec<usize> {
    let mut cols: Vec<Vec<f64>> = z.to_vec();
    let mut pins: Vec<usize> = Vec::with_capacity(z.len());
    for q in 0..cols.len() {
        let (j, _) = cols[q]
            .iter()
            .enumerate()
            .filter(|(j, _)| !pins.contains(j))
            .fold((0, -1.0), |best, (j, v)| {
                if v.abs() > best.1 {
                    (j, v.abs())
                } else {
                    best
                }
            });
        let pivot = cols[q][j];
        for r in q + 1..cols.len() {
            let f = cols[r][j] / pivot;
            let (head, tail) = cols.split_at_mut(r);
            tail[0]
                .iter_mut()
                .zip(&head[q])
                .for_each(|(x, y)| *x -= f * y);
        }
        pins.push(j);
    }
    pins
}
