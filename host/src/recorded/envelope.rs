//! A bounded min/max envelope of the four channels against time, for the figures: at most
//! [`MAX_BUCKETS`] buckets; when they are full, neighbours are merged in pairs and each
//! bucket then covers twice as many samples. Memory does not grow with the record, and every
//! peak stays visible.

use super::spectrum::CH;

/// Most buckets kept (even).
pub const MAX_BUCKETS: usize = 2048;

/// The samples of one bucket.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bucket {
    /// Time of its first and last sample [s].
    pub t0: f64,
    pub t1: f64,
    pub min: [f64; CH],
    pub max: [f64; CH],
}

impl Bucket {
    fn new(t: f64, a: &[f64; CH]) -> Self {
        Bucket { t0: t, t1: t, min: *a, max: *a }
    }
    fn add(&mut self, t: f64, a: &[f64; CH]) {
        self.t1 = t;
        for c in 0..CH {
            self.min[c] = self.min[c].min(a[c]);
            self.max[c] = self.max[c].max(a[c]);
        }
    }
    fn merge(&mut self, o: &Bucket) {
        self.t1 = o.t1;
        for c in 0..CH {
            self.min[c] = self.min[c].min(o.min[c]);
            self.max[c] = self.max[c].max(o.max[c]);
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct Envelope {
    per: u64,
    buckets: Vec<Bucket>,
    cur: Option<Bucket>,
    cur_n: u64,
}

impl Envelope {
    pub fn new() -> Self {
        Envelope { per: 1, buckets: Vec::with_capacity(MAX_BUCKETS), cur: None, cur_n: 0 }
    }

    /// Samples per complete bucket.
    pub fn samples_per_bucket(&self) -> u64 {
        self.per
    }

    #[inline]
    pub fn push(&mut self, t: f64, a: &[f64; CH]) {
        match &mut self.cur {
            Some(b) => b.add(t, a),
            None => self.cur = Some(Bucket::new(t, a)),
        }
        self.cur_n += 1;
        if self.cur_n >= self.per {
            self.buckets.extend(self.cur.take());
            self.cur_n = 0;
            if self.buckets.len() >= MAX_BUCKETS {
                let merged: Vec<Bucket> = self
                    .buckets
                    .chunks(2)
                    .map(|p| {
                        let mut b = p[0];
                        if let Some(o) = p.get(1) {
                            b.merge(o);
                        }
                        b
                    })
                    .collect();
                self.buckets.clear();
                self.buckets.extend(merged);
                self.per *= 2;
            }
        }
    }

    /// The buckets, the last one possibly partial.
    pub fn finish(mut self) -> Vec<Bucket> {
        self.buckets.extend(self.cur.take());
        self.buckets
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_and_keeps_extremes() {
        let mut e = Envelope::new();
        let n = 100_003u64;
        for i in 0..n {
            let v = if i == 77_777 { 9.0 } else if i == 5 { -4.0 } else { (i % 7) as f64 };
            e.push(i as f64, &[v; CH]);
        }
        let b = e.finish();
        assert!(b.len() <= MAX_BUCKETS);
        assert_eq!(b.iter().map(|b| b.max[0]).fold(f64::MIN, f64::max), 9.0);
        assert_eq!(b.iter().map(|b| b.min[2]).fold(f64::MAX, f64::min), -4.0);
        assert_eq!(b[0].t0, 0.0);
        assert_eq!(b.last().unwrap().t1, (n - 1) as f64);
    }
}
