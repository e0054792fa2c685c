//! Splitting a series at its gaps and clipping it to a rectangle.

/// The polylines of a series: the maximal runs of consecutive points whose coordinates
/// are both finite (a non-finite point is a gap).
pub fn polylines(points: &[(f64, f64)]) -> Vec<&[(f64, f64)]> {
    points
        .split(|(x, y)| !(x.is_finite() && y.is_finite()))
        .filter(|run| !run.is_empty())
        .collect()
}

/// The parts of the polylines of `points` inside the rectangle `x_range × y_range`
/// (with a hair of slack so that points on the edge stay), each segment clipped
/// (Liang–Barsky): a curve leaving the rectangle is cut where it leaves and resumes
/// where it comes back.
pub(crate) fn clip(
    points: &[(f64, f64)],
    x_range: (f64, f64),
    y_range: (f64, f64),
) -> Vec<Vec<(f64, f64)>> {
    let slack_x = (x_range.1 - x_range.0).abs() * 1e-9;
    let slack_y = (y_range.1 - y_range.0).abs() * 1e-9;
    let bounds = (
        x_range.0 - slack_x,
        x_range.1 + slack_x,
        y_range.0 - slack_y,
        y_range.1 + slack_y,
    );
    let inside =
        |(x, y): (f64, f64)| x >= bounds.0 && x <= bounds.1 && y >= bounds.2 && y <= bounds.3;
    let mut out = Vec::new();
    for line in polylines(points) {
        if line.iter().all(|&p| inside(p)) {
            out.push(line.to_vec());
            continue;
        }
        let mut current: Vec<(f64, f64)> = Vec::new();
        if line.len() == 1 {
            continue;
        }
        for pair in line.windows(2) {
            match clip_segment(pair[0], pair[1], bounds) {
                Some((a, b)) => {
                    if current.last() != Some(&a) {
                        if current.len() > 1 {
                            out.push(std::mem::take(&mut current));
                        }
                        current.clear();
                        current.push(a);
                    }
                    current.push(b);
                }
                None => {
                    if current.len() > 1 {
                        out.push(std::mem::take(&mut current));
                    }
                    current.clear();
                }
            }
        }
        if current.len() > 1 {
            out.push(current);
        }
    }
    out
}

/// The part of the segment `a`–`b` inside `(x_lo, x_hi, y_lo, y_hi)`, if any.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    (x_lo, x_hi, y_lo, y_hi): (f64, f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x_lo),
        (dx, x_hi - a.0),
        (-dy, a.1 - y_lo),
        (dy, y_hi - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_split_a_series() {
        let nan = f64::NAN;
        let points = [
            (0.0, 1.0),
            (1.0, 2.0),
            (nan, nan),
            (2.0, 0.0),
            (3.0, nan),
            (nan, nan),
        ];
        let lines = polylines(&points);
        assert_eq!(lines, vec![&points[0..2], &points[3..4]]);
        assert!(polylines(&[]).is_empty());
    }

    #[test]
    fn curves_are_clipped_to_a_fixed_range() {
        let points = [(0.0, 0.0), (1.0, 10.0), (2.0, 0.0), (3.0, 0.5)];
        let lines = clip(&points, (0.0, 3.0), (-1.0, 1.0));
        assert_eq!(lines.len(), 2);
        let near = |a: &[(f64, f64)], b: &[(f64, f64)]| {
            a.len() == b.len()
                && a.iter()
                    .zip(b)
                    .all(|(p, q)| (p.0 - q.0).abs() < 1e-6 && (p.1 - q.1).abs() < 1e-6)
        };
        assert!(near(&lines[0], &[(0.0, 0.0), (0.1, 1.0)]), "{lines:?}");
        assert!(
            near(&lines[1], &[(1.9, 1.0), (2.0, 0.0), (3.0, 0.5)]),
            "{lines:?}"
        );
        assert_eq!(
            clip(&points, (0.0, 3.0), (-1.0, 20.0)),
            vec![points.to_vec()]
        );
    }
}
