//! The symbolic analysis of the sparse LU factorization: a fill-reducing elimination
//! order by Markowitz's criterion restricted to the diagonal, and the exact structure
//! of the factors (see [`super::sparse`] for how they are used).
//!
//! Every data structure is linear in the entries of the pattern and of the factors:
//! the matrix still to be factored is held as one list of columns per row and one
//! list of rows per column, in two pools of indices (a list that gains entries moves
//! to the end of its pool; a full pool is compacted into a spare one), and the next
//! pivot is the top of a binary heap keyed by the Markowitz count, into which the
//! states whose row or column an elimination step changes are pushed again (outdated
//! entries are skipped when they come up). A step costs
//! `O(|r| |c| + (|r| + |c|) log n)` for a pivot row `r` and column `c`, so the whole
//! analysis is `O(flops + nnz log n)`, with `flops` the multiply-adds of one
//! factorization: linear in the size of the model for bounded fill, where scanning
//! every state for each pivot (and `n × n` bit matrices) was quadratic.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// The factors would need more entries than the storage holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TooLarge;

/// A pattern to analyse: for each row, its columns (compressed rows, each row's
/// columns increasing), of which only the entries marked `active` count when given.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rows<'a> {
    /// Where each row starts in `cols` (`n + 1` entries).
    pub row_start: &'a [usize],
    /// The columns, row after row.
    pub cols: &'a [usize],
    /// Whether each entry (in the order of `cols`) counts.
    pub active: Option<&'a [bool]>,
}

impl Rows<'_> {
    fn n(&self) -> usize {
        self.row_start.len() - 1
    }

    /// The counted columns of row `i`.
    fn row(&self, i: usize) -> impl Iterator<Item = usize> + '_ {
        let range = self.row_start[i]..self.row_start[i + 1];
        let active = self.active;
        range
            .filter(move |&e| active.is_none_or(|a| a[e]))
            .map(|e| self.cols[e])
    }

    /// Where entry `(i, j)` is in `cols`, if it is there (counted or not).
    fn position(&self, i: usize, j: usize) -> Option<usize> {
        let start = self.row_start[i];
        self.cols[start..self.row_start[i + 1]]
            .binary_search(&j)
            .ok()
            .map(|k| start + k)
    }
}

/// The elimination order of an `n × n` pattern (with its diagonal) and the structure
/// of its LU factors.
#[derive(Clone, Debug)]
pub(crate) struct Symbolic {
    pub n: usize,
    /// `perm[k]`: the state (row and column of `A`) eliminated at step `k`.
    pub perm: Vec<usize>,
    /// Row `k` of the factors (of state `perm[k]`) is held in positions
    /// `row_start[k]..row_start[k + 1]`: first `L` (columns eliminated earlier, in
    /// elimination order), then the diagonal at `diag[k]`, then `U`.
    pub row_start: Vec<usize>,
    pub diag: Vec<usize>,
    /// Each entry's column, as an elimination step (`nnz` used, the rest capacity).
    pub step: Vec<u32>,
    /// Each entry's column, as a state.
    pub col: Vec<u32>,
    /// Each entry's position in the analysed pattern's `cols` (the Jacobian's values),
    /// or [`Symbolic::NONE`] for an entry that is not there (fill-in, the diagonal).
    pub src: Vec<usize>,
    pub nnz: usize,
    /// Multiply-adds of one real factorization.
    pub flops: usize,
}

impl Symbolic {
    /// [`Symbolic::src`] of an entry that is not in the pattern.
    pub const NONE: usize = usize::MAX;

    /// Storage for the structure of `n × n` factors with up to `capacity` entries.
    pub fn with_capacity(n: usize, capacity: usize) -> Self {
        Symbolic {
            n,
            perm: vec![0; n],
            row_start: vec![0; n + 1],
            diag: vec![0; n],
            step: vec![0; capacity],
            col: vec![0; capacity],
            src: vec![0; capacity],
            nnz: 0,
            flops: 0,
        }
    }

    /// The entries the storage holds at most.
    pub fn capacity(&self) -> usize {
        self.step.len()
    }

    /// The elimination order: `order()[k]` is the state eliminated at step `k`.
    pub fn order(&self) -> &[usize] {
        &self.perm
    }
}

/// One list of indices per state, in a pool (and a spare pool for compaction).
#[derive(Clone, Debug, Default)]
struct Lists {
    start: Vec<usize>,
    len: Vec<usize>,
    pool: Vec<u32>,
    spare: Vec<u32>,
    /// The used part of `pool`.
    end: usize,
}

impl Lists {
    fn new(n: usize, capacity: usize) -> Self {
        Lists {
            start: vec![0; n],
            len: vec![0; n],
            pool: vec![0; capacity],
            spare: vec![0; capacity],
            end: 0,
        }
    }

    fn list(&self, v: usize) -> &[u32] {
        &self.pool[self.start[v]..self.start[v] + self.len[v]]
    }

    /// Makes room for a list of `len` entries at the end of the pool: compacts the
    /// lists of the states still `alive` (and `keep`), and grows the pools when `grow`.
    fn reserve(
        &mut self,
        len: usize,
        alive: &[bool],
        keep: usize,
        grow: bool,
    ) -> Result<(), TooLarge> {
        if self.end + len <= self.pool.len() {
            return Ok(());
        }
        let mut next = 0;
        for (v, &alive) in alive.iter().enumerate() {
            if !alive && v != keep {
                self.len[v] = 0;
            }
            let (s, l) = (self.start[v], self.len[v]);
            self.spare[next..next + l].copy_from_slice(&self.pool[s..s + l]);
            self.start[v] = next;
            next += l;
        }
        core::mem::swap(&mut self.pool, &mut self.spare);
        self.end = next;
        // A growable pool is kept at most half full after compaction, so that
        // compactions stay rare (a fixed one is sized so at set-up).
        let limit = if grow {
            self.pool.len() / 2
        } else {
            self.pool.len()
        };
        if self.end + len <= limit {
            return Ok(());
        }
        if !grow {
            return Err(TooLarge);
        }
        let size = (2 * self.pool.len()).max(2 * (self.end + len));
        self.pool.resize(size, 0);
        self.spare.resize(size, 0);
        Ok(())
    }

    /// Appends a new list for `v` holding `entries` (placed at the end of the pool,
    /// which must have room).
    fn push_list(&mut self, v: usize, entries: impl Iterator<Item = u32>) {
        self.start[v] = self.end;
        let mut len = 0;
        for e in entries {
            self.pool[self.end + len] = e;
            len += 1;
        }
        self.len[v] = len;
        self.end += len;
    }

    /// Removes `x` from `v`'s list (order is not kept).
    fn remove(&mut self, v: usize, x: u32) {
        let (s, l) = (self.start[v], self.len[v]);
        let list = &mut self.pool[s..s + l];
        if let Some(p) = list.iter().position(|&e| e == x) {
            list.swap(p, l - 1);
            self.len[v] -= 1;
        }
    }
}

/// The work space of the symbolic analysis, allocated once: [`Analyser::analyse`]
/// allocates nothing unless it was made growable (at set-up).
#[derive(Clone, Debug)]
pub(crate) struct Analyser {
    /// The matrix still to be factored: each state's row (columns) and column (rows),
    /// the diagonal included.
    rows: Lists,
    cols: Lists,
    alive: Vec<bool>,
    /// The alive states by [`Analyser::key`], least first, with outdated entries
    /// (capacity `n` plus the factors' entries: one entry per change of a key).
    queue: BinaryHeap<Reverse<(usize, usize, usize)>>,
    /// `mark[j] == stamp`: `j` is in the list being merged.
    mark: Vec<usize>,
    stamp: usize,
    /// The pivot's row and column (without it), copied out of the pools.
    pivot_row: Vec<u32>,
    pivot_col: Vec<u32>,
    position: Vec<usize>,
    /// The factors as eliminated: the `U` row of step `k` (as states) at
    /// `u[u_start[k]..u_start[k + 1]]`, and the `L` entries as (state, step) pairs.
    u_start: Vec<usize>,
    u: Vec<u32>,
    l: Vec<(u32, u32)>,
    /// The `L` steps of each state, bucketed from `l`.
    l_start: Vec<usize>,
    l_sorted: Vec<u32>,
    /// Whether the storage may grow (set-up) or must not (during a run).
    grow: bool,
}

impl Analyser {
    /// The work space for `n` states and factors of up to `capacity` entries; `grow`
    /// lets [`Analyser::analyse`] allocate more when needed.
    pub fn new(n: usize, capacity: usize, grow: bool) -> Self {
        let pool = 2 * (capacity + n);
        Analyser {
            rows: Lists::new(n, pool),
            cols: Lists::new(n, pool),
            alive: vec![false; n],
            queue: BinaryHeap::with_capacity(capacity + n),
            mark: vec![0; n],
            stamp: 0,
            pivot_row: Vec::with_capacity(n),
            pivot_col: Vec::with_capacity(n),
            position: vec![0; n],
            u_start: vec![0; n + 1],
            u: vec![0; capacity],
            l: vec![(0, 0); capacity],
            l_start: vec![0; n + 1],
            l_sorted: vec![0; capacity],
            grow,
        }
    }

    /// Analyses `pattern` (the diagonal is added) into `out`, in Markowitz order or,
    /// when given, in `order`; fails, leaving `out` to be analysed again, if the factors
    /// do not fit its storage (or, unless growable, the work space).
    pub fn analyse(
        &mut self,
        pattern: Rows<'_>,
        order: Option<&[usize]>,
        out: &mut Symbolic,
    ) -> Result<(), TooLarge> {
        let n = pattern.n();
        if self.grow && out.capacity() > self.u.len() {
            let c = out.capacity();
            self.u.resize(c, 0);
            self.l.resize(c, (0, 0));
            self.l_sorted.resize(c, 0);
        }
        let capacity = out.capacity().min(self.u.len());
        let (nnz, flops) = self.eliminate(pattern, order, &mut out.perm, capacity)?;
        self.build(pattern, out);
        out.n = n;
        out.nnz = nnz;
        out.flops = flops;
        Ok(())
    }

    /// The entries of the factors and the multiply-adds of one factorization of
    /// `pattern` in Markowitz order, growing the storage as needed (set-up only).
    pub fn count(&mut self, pattern: Rows<'_>, perm: &mut [usize]) -> (usize, usize) {
        assert!(self.grow, "only a growable analyser counts");
        self.eliminate(pattern, None, perm, usize::MAX)
            .expect("a growable analyser has room")
    }

    /// The Markowitz count of `v` and its tie-breaks: `(r - 1)(c - 1)`, then `r + c`,
    /// then the lower index.
    #[inline]
    fn key(&self, v: usize) -> (usize, usize, usize) {
        let (r, c) = (self.rows.len[v], self.cols.len[v]);
        ((r - 1) * (c - 1), r + c, v)
    }

    /// Queues `v` with its current key; when the queue is full, rebuilds it from the
    /// states still alive (dropping the outdated entries).
    fn requeue(&mut self, v: usize) {
        if self.queue.len() == self.queue.capacity() && !self.grow {
            self.queue.clear();
            for u in 0..self.alive.len() {
                if self.alive[u] && u != v {
                    self.queue.push(Reverse(self.key(u)));
                }
            }
        }
        self.queue.push(Reverse(self.key(v)));
    }

    /// The alive state of least key. A state's key changes only when its row or column
    /// does, and it is queued again then: an entry whose key is no longer its state's
    /// (or whose state is eliminated) is outdated and skipped.
    fn pop(&mut self) -> usize {
        loop {
            let Reverse(key) = self.queue.pop().expect("a state is left");
            let v = key.2;
            if self.alive[v] && self.key(v) == key {
                return v;
            }
        }
    }

    /// Replaces the list of each state in `targets` (in `lists`) by itself without
    /// `v`, merged with `add`; the other side's lists are not touched.
    #[allow(clippy::too_many_arguments)]
    fn merge(
        lists: &mut Lists,
        targets: &[u32],
        add: &[u32],
        v: usize,
        alive: &[bool],
        mark: &mut [usize],
        stamp: &mut usize,
        grow: bool,
    ) -> Result<(), TooLarge> {
        for &i in targets {
            let i = i as usize;
            *stamp += 1;
            for &j in lists.list(i) {
                mark[j as usize] = *stamp;
            }
            let new = add.iter().filter(|&&j| mark[j as usize] != *stamp).count();
            if new == 0 {
                lists.remove(i, v as u32);
                continue;
            }
            // The old list is copied whole (then `v` dropped): room for it and the new.
            lists.reserve(lists.len[i] + new, alive, v, grow)?;
            let (s, l) = (lists.start[i], lists.len[i]);
            let end = lists.end;
            lists.pool.copy_within(s..s + l, end);
            lists.start[i] = end;
            lists.end += l;
            lists.remove(i, v as u32);
            lists.end -= 1;
            let stamp = *stamp;
            let extra = add.iter().copied().filter(|&j| mark[j as usize] != stamp);
            let at = lists.end;
            for (k, j) in extra.enumerate() {
                lists.pool[at + k] = j;
            }
            lists.len[i] += new;
            lists.end += new;
        }
        Ok(())
    }

    /// The symbolic elimination of `pattern` (plus the diagonal) in Markowitz order or
    /// in `order`, writing the order into `perm` and keeping the factors' rows (up to
    /// `capacity` entries); returns the factors' entries and the multiply-adds of a real
    /// factorization.
    fn eliminate(
        &mut self,
        pattern: Rows<'_>,
        order: Option<&[usize]>,
        perm: &mut [usize],
        capacity: usize,
    ) -> Result<(usize, usize), TooLarge> {
        let n = pattern.n();
        let grow = self.grow;
        // The rows (with the diagonal), then the columns by transposition.
        self.alive.fill(true);
        self.rows.end = 0;
        self.cols.end = 0;
        self.rows.len.fill(0);
        self.cols.len.fill(0);
        let total = pattern.row_start[n] + n;
        self.rows.reserve(total, &self.alive, n, grow)?;
        self.cols.reserve(total, &self.alive, n, grow)?;
        self.cols.len.fill(0);
        for i in 0..n {
            let has_diagonal = pattern.row(i).any(|j| j == i);
            let diagonal = (!has_diagonal).then_some(i);
            let entries = pattern.row(i).chain(diagonal).map(|j| j as u32);
            self.rows.push_list(i, entries);
            for &j in self.rows.list(i) {
                self.cols.len[j as usize] += 1;
            }
        }
        let mut next = 0;
        for j in 0..n {
            self.cols.start[j] = next;
            next += self.cols.len[j];
            self.cols.len[j] = 0;
        }
        self.cols.end = next;
        for i in 0..n {
            for k in self.rows.start[i]..self.rows.start[i] + self.rows.len[i] {
                let j = self.rows.pool[k] as usize;
                self.cols.pool[self.cols.start[j] + self.cols.len[j]] = i as u32;
                self.cols.len[j] += 1;
            }
        }
        self.queue.clear();
        if order.is_none() {
            for v in 0..n {
                self.requeue(v);
            }
        }
        let (mut nnz, mut flops, mut used_u, mut used_l) = (n, 0, 0, 0);
        for k in 0..n {
            let v = match order {
                Some(order) => order[k],
                None => self.pop(),
            };
            self.alive[v] = false;
            perm[k] = v;
            self.position[v] = k;
            self.pivot_row.clear();
            self.pivot_col.clear();
            let (row, col) = (self.rows.list(v), self.cols.list(v));
            self.pivot_row
                .extend(row.iter().filter(|&&j| j as usize != v));
            self.pivot_col
                .extend(col.iter().filter(|&&i| i as usize != v));
            let (below, right) = (self.pivot_col.len(), self.pivot_row.len());
            nnz += below + right;
            flops += below * (right + 1);
            if nnz > capacity {
                return Err(TooLarge);
            }
            let need = (used_u + right).max(used_l + below);
            if need > self.u.len() {
                if !grow {
                    return Err(TooLarge);
                }
                let size = (2 * self.u.len()).max(need);
                self.u.resize(size, 0);
                self.l.resize(size, (0, 0));
                self.l_sorted.resize(size, 0);
            }
            self.u_start[k] = used_u;
            self.u[used_u..used_u + right].copy_from_slice(&self.pivot_row);
            used_u += right;
            for &i in &self.pivot_col {
                self.l[used_l] = (i, k as u32);
                used_l += 1;
            }
            // Rows with an entry in column v receive row v's pattern (fill-in), and
            // columns with an entry in row v receive column v's.
            let (alive, mark) = (&self.alive, &mut self.mark);
            Self::merge(
                &mut self.rows,
                &self.pivot_col,
                &self.pivot_row,
                v,
                alive,
                mark,
                &mut self.stamp,
                grow,
            )?;
            Self::merge(
                &mut self.cols,
                &self.pivot_row,
                &self.pivot_col,
                v,
                alive,
                mark,
                &mut self.stamp,
                grow,
            )?;
            if order.is_none() {
                for p in 0..self.pivot_col.len() {
                    self.requeue(self.pivot_col[p] as usize);
                }
                for p in 0..self.pivot_row.len() {
                    self.requeue(self.pivot_row[p] as usize);
                }
            }
        }
        self.u_start[n] = used_u;
        // The L entries by state, steps increasing (they were recorded in step order).
        self.l_start.fill(0);
        for &(i, _) in &self.l[..used_l] {
            self.l_start[i as usize + 1] += 1;
        }
        for i in 0..n {
            self.l_start[i + 1] += self.l_start[i];
        }
        // `mark` serves as the fill pointer of each state here.
        self.mark[..n].copy_from_slice(&self.l_start[..n]);
        for &(i, k) in &self.l[..used_l] {
            let i = i as usize;
            self.l_sorted[self.mark[i]] = k;
            self.mark[i] += 1;
        }
        self.mark.fill(0);
        self.stamp = 0;
        Ok((nnz, flops))
    }

    /// Writes the rows of the factors kept by the last [`Analyser::eliminate`] into
    /// `out` (whose `perm` holds its order and whose storage is large enough).
    fn build(&mut self, pattern: Rows<'_>, out: &mut Symbolic) {
        let n = pattern.n();
        let mut next = 0;
        out.row_start[0] = 0;
        for k in 0..n {
            let s = out.perm[k];
            let upper = &mut self.u[self.u_start[k]..self.u_start[k + 1]];
            let position = &self.position;
            upper.sort_unstable_by_key(|&j| position[j as usize]);
            let lower = self.l_sorted[self.l_start[s]..self.l_start[s + 1]]
                .iter()
                .map(|&kk| (kk as usize, out.perm[kk as usize]));
            let diagonal = core::iter::once((k, s));
            let upper = upper.iter().map(|&j| (position[j as usize], j as usize));
            for (step, j) in lower.chain(diagonal).chain(upper) {
                if j == s {
                    out.diag[k] = next;
                }
                out.step[next] = step as u32;
                out.col[next] = j as u32;
                out.src[next] = pattern.position(s, j).unwrap_or(Symbolic::NONE);
                next += 1;
            }
            out.row_start[k + 1] = next;
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::*;

    /// A deterministic pseudo-random number in [0, 1) (a 64-bit LCG).
    fn rand(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Markowitz elimination by the definition: full scans over explicit sets. Returns
    /// the order, the factors' entries and the multiply-adds.
    fn reference(n: usize, rows: &[Vec<usize>]) -> (Vec<usize>, usize, usize) {
        let mut r: Vec<BTreeSet<usize>> =
            rows.iter().map(|r| r.iter().copied().collect()).collect();
        for (i, row) in r.iter_mut().enumerate() {
            row.insert(i);
        }
        let mut c: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
        for (i, row) in r.iter().enumerate() {
            for &j in row {
                c[j].insert(i);
            }
        }
        let mut alive = vec![true; n];
        let (mut order, mut nnz, mut flops) = (Vec::new(), n, 0);
        for _ in 0..n {
            let v = (0..n)
                .filter(|&v| alive[v])
                .min_by_key(|&v| {
                    (
                        (r[v].len() - 1) * (c[v].len() - 1),
                        r[v].len() + c[v].len(),
                        v,
                    )
                })
                .unwrap();
            alive[v] = false;
            order.push(v);
            let pr: Vec<usize> = r[v].iter().copied().filter(|&j| j != v).collect();
            let pc: Vec<usize> = c[v].iter().copied().filter(|&i| i != v).collect();
            nnz += pr.len() + pc.len();
            flops += pc.len() * (pr.len() + 1);
            for &i in &pc {
                r[i].remove(&v);
                r[i].extend(pr.iter().copied());
            }
            for &j in &pr {
                c[j].remove(&v);
                c[j].extend(pc.iter().copied());
            }
        }
        (order, nnz, flops)
    }

    /// The heap and the pools choose exactly the pivots of the definition (the order,
    /// hence the arithmetic of the factorizations, is the one of the scan over all
    /// states it replaces), with the same fill-in and cost, for random unsymmetric
    /// patterns of several densities, in pools small enough to be compacted and grown.
    #[test]
    fn markowitz_order_matches_the_definition() {
        let mut seed = 17;
        for (n, per_row) in [(1, 0), (2, 1), (7, 2), (30, 3), (80, 2), (120, 6), (200, 1)] {
            let rows: Vec<Vec<usize>> = (0..n)
                .map(|_| {
                    let mut row: Vec<usize> = (0..per_row)
                        .map(|_| (rand(&mut seed) * n as f64) as usize)
                        .collect();
                    row.sort_unstable();
                    row.dedup();
                    row
                })
                .collect();
            let (row_start, cols) = {
                let mut row_start = vec![0];
                let mut cols = Vec::new();
                for row in &rows {
                    cols.extend_from_slice(row);
                    row_start.push(cols.len());
                }
                (row_start, cols)
            };
            let pattern = Rows {
                row_start: &row_start,
                cols: &cols,
                active: None,
            };
            let (order, nnz, flops) = reference(n, &rows);
            let mut analyser = Analyser::new(n, 1, true);
            let mut perm = vec![0; n];
            assert_eq!(analyser.count(pattern, &mut perm), (nnz, flops), "n {n}");
            assert_eq!(perm, order, "n {n}");
            // Fixed storage of the right size: the same analysis, no growth needed.
            let mut fixed = Analyser::new(n, nnz, false);
            let mut sym = Symbolic::with_capacity(n, nnz);
            fixed.analyse(pattern, None, &mut sym).unwrap();
            assert_eq!((sym.order(), sym.nnz, sym.flops), (&order[..], nnz, flops));
            // Every row of the factors: L steps increasing, the diagonal, U steps
            // increasing; `src` points at the pattern's own entries.
            for k in 0..n {
                let entries = sym.row_start[k]..sym.row_start[k + 1];
                let steps = &sym.step[entries.clone()];
                assert!(steps.windows(2).all(|w| w[0] < w[1]), "row {k}");
                assert_eq!(sym.step[sym.diag[k]] as usize, k);
                for e in entries {
                    let (i, j) = (sym.perm[k], sym.col[e] as usize);
                    match rows[i].binary_search(&j) {
                        Ok(p) => assert_eq!(sym.src[e], row_start[i] + p),
                        Err(_) => assert_eq!(sym.src[e], Symbolic::NONE),
                    }
                }
            }
        }
    }
}
