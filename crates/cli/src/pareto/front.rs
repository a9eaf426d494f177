//! The front maths: which points no other beats, and how far the default is from its front.

/// Marks the points no other point beats in both time and error (ties keep both).
pub fn mark_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(t, e)| {
            !points
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}

/// The default (point 0)'s slack: its time over the fastest point at least as accurate, − 1.
pub fn default_slack(points: &[(f64, f64)]) -> f64 {
    let (t0, e0) = points[0];
    let best = points
        .iter()
        .filter(|p| p.1 <= e0)
        .map(|p| p.0)
        .fold(f64::INFINITY, f64::min);
    t0 / best - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_front_keeps_exactly_the_undominated_points() {
        let p = [
            (1.0, 0.5),
            (2.0, 0.3),
            (3.0, 0.4),
            (4.0, 0.1),
            (2.0, 0.3),
            (5.0, 0.1),
        ];
        assert_eq!(mark_front(&p), vec![true, true, false, true, true, false]);
    }

    #[test]
    fn the_default_slack_is_measured_from_the_fastest_point_as_accurate() {
        // Default 3 ms at 0.3; a 2 ms point reaches 0.25: slack 50 %.
        let s = default_slack(&[(3.0, 0.3), (2.0, 0.25), (1.0, 0.5)]);
        assert!((s - 0.5).abs() < 1e-12);
        // On its front: 0.
        assert_eq!(default_slack(&[(1.0, 0.3), (2.0, 0.2)]), 0.0);
    }
}
