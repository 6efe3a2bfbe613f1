//! Generation marks: a set over `0..len` cleared in O(1) by starting a new generation, so that
//! an operation's bookkeeping costs what it touches, not the grid's size.

/// A set of indices, emptied by [`Marks::start`] without touching its storage (each index
/// holds the generation it was last marked in; the set is the indices of the present one).
#[derive(Debug, Clone, Default)]
pub(crate) struct Marks {
    marks: Vec<u32>,
    stamp: u32,
}

impl Marks {
    /// Empties the set, for indices `0..len`.
    pub(crate) fn start(&mut self, len: usize) {
        if self.marks.len() != len {
            self.marks.clear();
            self.marks.resize(len, 0);
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            // The counter wrapped: every old mark could look current.
            self.marks.fill(0);
            self.stamp = 1;
        }
    }

    /// Adds `i`; `true` when it was not in the set.
    #[inline]
    pub(crate) fn mark(&mut self, i: usize) -> bool {
        let fresh = self.marks[i] != self.stamp;
        self.marks[i] = self.stamp;
        fresh
    }

    /// Adds `i`.
    #[inline]
    pub(crate) fn set(&mut self, i: usize) {
        self.marks[i] = self.stamp;
    }

    /// Whether `i` is in the set.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> bool {
        self.marks[i] == self.stamp
    }
}

#[cfg(test)]
mod tests {
    use super::Marks;

    #[test]
    fn a_new_generation_empties_the_set_even_when_the_counter_wraps() {
        let mut m = Marks::default();
        m.start(4);
        assert!(m.mark(2));
        assert!(!m.mark(2));
        assert!(m.get(2) && !m.get(1));
        m.stamp = u32::MAX;
        m.set(3);
        m.start(4);
        assert!(!m.get(3) && !m.get(2), "wrapped generation kept a mark");
        m.start(6);
        assert!((0..6).all(|i| !m.get(i)));
    }
}
