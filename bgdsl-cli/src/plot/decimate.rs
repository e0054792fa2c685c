//! Thinning a series for display, keeping its extremes: a chart is a few hundred pixel
//! columns wide, so a million samples draw no more than a few thousand points do, and
//! an image (or a page that inlines it) stays small whatever the run's length.
//!
//! A series whose polylines hold more than [`POINTS_PER_COLUMN`] points per pixel
//! column in all is thinned. Each polyline whose x moves one way keeps, in every pixel
//! column it crosses, its first, lowest, highest and last point in drawing order (the
//! M4 rule: the line drawn through them covers the same pixels as the whole one, so no
//! peak is lost). When that still leaves too many points (many overlaid polylines, such
//! as hundreds of crank revolutions on one angle axis, or x going back and forth), the
//! series is drawn as its envelope instead: the lowest and the highest value in each
//! pixel column, over every sample, as two polylines (a dashed series always is, when
//! it is thinned).

/// A series is thinned when it has more than this many points per pixel column.
pub const POINTS_PER_COLUMN: usize = 8;

/// A series' polylines after thinning, and how many points they had and kept.
#[derive(Clone, Debug, PartialEq)]
pub struct Thinned {
    /// The polylines to draw.
    pub lines: Vec<Vec<(f64, f64)>>,
    /// The points before thinning.
    pub total: usize,
    /// The points kept.
    pub kept: usize,
}

impl Thinned {
    /// Whether points were dropped.
    pub fn decimated(&self) -> bool {
        self.kept < self.total
    }
}

/// `lines` thinned for a plot `columns` pixels wide spanning `x_range` (see the
/// [module documentation](self)). Lines with few enough points come back as they are.
/// With `envelope_only`, a series that is thinned is always drawn as its envelope (for
/// a dashed line: the M4 points of an oscillating signal zigzag up and down each
/// column, and dashes along that path would be thousands of tiny elements).
pub fn for_display(
    lines: Vec<Vec<(f64, f64)>>,
    x_range: (f64, f64),
    columns: usize,
    envelope_only: bool,
) -> Thinned {
    let columns = columns.max(1);
    let total: usize = lines.iter().map(Vec::len).sum();
    let budget = POINTS_PER_COLUMN * columns;
    if total <= budget || x_range.1.partial_cmp(&x_range.0) != Some(core::cmp::Ordering::Greater) {
        return Thinned {
            lines,
            total,
            kept: total,
        };
    }
    let column = |x: f64| {
        let c = ((x - x_range.0) / (x_range.1 - x_range.0) * columns as f64).floor();
        c.clamp(0.0, (columns - 1) as f64) as usize
    };
    let thinned: Option<Vec<Vec<(f64, f64)>>> = lines
        .iter()
        .map(|line| (!envelope_only && monotone(line)).then(|| m4(line, &column)))
        .collect();
    let lines = match thinned {
        Some(thinned) if thinned.iter().map(Vec::len).sum::<usize>() <= budget => thinned,
        _ => envelope(&lines, x_range, columns, &column),
    };
    let kept = lines.iter().map(Vec::len).sum();
    Thinned { lines, total, kept }
}

/// Whether x never turns back along `line`.
fn monotone(line: &[(f64, f64)]) -> bool {
    line.windows(2).all(|w| w[1].0 >= w[0].0) || line.windows(2).all(|w| w[1].0 <= w[0].0)
}

/// The first, lowest, highest and last point of each run of points in one pixel
/// column, in drawing order.
fn m4(line: &[(f64, f64)], column: &impl Fn(f64) -> usize) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut start = 0;
    while start < line.len() {
        let c = column(line[start].0);
        let end = line[start..]
            .iter()
            .position(|p| column(p.0) != c)
            .map_or(line.len(), |n| start + n);
        let run = &line[start..end];
        let (mut low, mut high) = (0, 0);
        for (i, p) in run.iter().enumerate() {
            if p.1 < run[low].1 {
                low = i;
            }
            if p.1 > run[high].1 {
                high = i;
            }
        }
        let mut picks = [0, low, high, run.len() - 1];
        picks.sort_unstable();
        let mut previous = None;
        for i in picks {
            if previous != Some(i) {
                out.push(run[i]);
                previous = Some(i);
            }
        }
        start = end;
    }
    out
}

/// The lowest and the highest value of every pixel column over all `lines`, as two
/// polylines through the columns' centres (broken where a column has no point).
fn envelope(
    lines: &[Vec<(f64, f64)>],
    x_range: (f64, f64),
    columns: usize,
    column: &impl Fn(f64) -> usize,
) -> Vec<Vec<(f64, f64)>> {
    let mut bounds: Vec<Option<(f64, f64)>> = vec![None; columns];
    for &(x, y) in lines.iter().flatten() {
        let slot = &mut bounds[column(x)];
        *slot = Some(match *slot {
            None => (y, y),
            Some((lo, hi)) => (lo.min(y), hi.max(y)),
        });
    }
    let width = (x_range.1 - x_range.0) / columns as f64;
    let centre = |c: usize| x_range.0 + (c as f64 + 0.5) * width;
    let mut out = Vec::new();
    for pick in [|b: (f64, f64)| b.0, |b: (f64, f64)| b.1] {
        let mut current = Vec::new();
        for (c, b) in bounds.iter().enumerate() {
            match b {
                Some(b) => current.push((centre(c), pick(*b))),
                None if !current.is_empty() => out.push(std::mem::take(&mut current)),
                None => {}
            }
        }
        if !current.is_empty() {
            out.push(current);
        }
    }
    out
}

/// `n` with a comma between thousands: `955,001`.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_thousands() {
        assert_eq!(thousands(955_001), "955,001");
        assert_eq!(thousands(100), "100");
        assert_eq!(thousands(1_000_000), "1,000,000");
    }

    #[test]
    fn short_series_are_left_alone() {
        let line: Vec<(f64, f64)> = (0..100).map(|i| (i as f64, (i as f64).sin())).collect();
        let thinned = for_display(vec![line.clone()], (0.0, 99.0), 800, false);
        assert!(!thinned.decimated());
        assert_eq!(thinned.lines, [line]);
    }

    #[test]
    fn a_long_series_keeps_its_peaks_within_the_budget() {
        let n = 1_000_001;
        let mut line: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let t = i as f64 * 1e-3;
                (t, (t * 7.0).sin())
            })
            .collect();
        line[123_457].1 = 40.0; // a one-sample spike
        line[876_543].1 = -25.0;
        let thinned = for_display(vec![line.clone()], (0.0, 1000.0), 900, false);
        assert!(thinned.decimated());
        assert_eq!(thinned.total, n);
        assert!(thinned.kept <= 4 * 900, "{}", thinned.kept);
        let ys = thinned.lines.iter().flatten().map(|p| p.1);
        let (lo, hi) = ys.fold((f64::MAX, f64::MIN), |(lo, hi), y| (lo.min(y), hi.max(y)));
        assert_eq!((lo, hi), (-25.0, 40.0));
        let xs: Vec<f64> = thinned.lines[0].iter().map(|p| p.0).collect();
        assert!(xs.windows(2).all(|w| w[1] >= w[0]), "drawing order kept");
        let envelope = for_display(vec![line], (0.0, 1000.0), 900, true);
        assert_eq!(envelope.lines.len(), 2);
        assert_eq!(envelope.kept, 2 * 900);
    }

    #[test]
    fn many_overlaid_lines_become_their_envelope() {
        // 500 revolutions of 1000 points each on one angle axis.
        let lines: Vec<Vec<(f64, f64)>> = (0..500)
            .map(|r| {
                (0..1000)
                    .map(|i| {
                        let a = i as f64 * core::f64::consts::TAU / 1000.0;
                        (a, a.sin() + if r == 3 { 0.5 } else { 0.0 })
                    })
                    .collect()
            })
            .collect();
        let thinned = for_display(lines, (0.0, core::f64::consts::TAU), 400, false);
        assert_eq!(thinned.total, 500_000);
        assert_eq!(thinned.lines.len(), 2);
        assert_eq!(thinned.kept, 800);
        let top = thinned.lines[1]
            .iter()
            .map(|p| p.1)
            .fold(f64::MIN, f64::max);
        assert!((top - 1.5).abs() < 1e-3, "{top}");
    }
}
