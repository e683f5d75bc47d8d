//! Keyframe animations of node transforms (glTF 2.0 §3.11) and their sampling, as the
//! specification's Appendix C defines it: the end values outside the keys, STEP holds the
//! previous key, LINEAR interpolates (slerp for rotations, the shortest way round), and
//! CUBICSPLINE follows a cubic Hermite spline whose tangents are scaled by the key interval.
//!
//! The values of a channel are checked by the loader (finite, times strictly increasing,
//! rotations non-zero); sampling itself never fails and never produces NaN from such values.

use glam::Vec4;

/// One glTF animation: channels that move node transforms over time. All animations of a
/// scene play at once, from the same clock (see [`crate::Scene::pose_at`]).
#[derive(Clone, Debug, Default)]
pub struct Animation {
    /// The glTF animation's name, or `animation N`.
    pub name: String,
    /// Its channels that move nodes of the scene, in file order.
    pub channels: Vec<Channel>,
    /// Seconds added to the scene's clock before its channels are sampled (an inserted
    /// model's `time_offset`).
    pub time_offset: f32,
}

/// The node property a channel animates (glTF `target.path`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TargetPath {
    /// The node's translation (xyz of the values).
    Translation,
    /// The node's rotation, a quaternion (xyzw of the values).
    Rotation,
    /// The node's scale (xyz of the values).
    Scale,
    /// The morph-target weights of the node's mesh: this many, four per value (a key's
    /// value is `ceil(count / 4)` consecutive values, the last padded with zeros).
    Weights(usize),
}

impl TargetPath {
    /// The glTF name: `translation`, `rotation`, `scale`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Translation => "translation",
            Self::Rotation => "rotation",
            Self::Scale => "scale",
            Self::Weights(_) => "weights",
        }
    }

    /// Values (of four components) per key value: `ceil(count / 4)` for weights, else 1.
    pub fn chunks(self) -> usize {
        match self {
            Self::Weights(count) => count.div_ceil(4).max(1),
            _ => 1,
        }
    }
}

/// How a channel's value between two keys is found (glTF 2.0 Appendix C).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the previous key.
    Step,
    /// Linear interpolation; spherical (slerp) for rotations.
    Linear,
    /// A cubic Hermite spline: each key has an in-tangent, a value and an out-tangent.
    CubicSpline,
}

impl Interpolation {
    /// The glTF name: `STEP`, `LINEAR`, `CUBICSPLINE`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Step => "STEP",
            Self::Linear => "LINEAR",
            Self::CubicSpline => "CUBICSPLINE",
        }
    }

    /// Output values per key: 3 for CUBICSPLINE (in-tangent, value, out-tangent), else 1.
    pub fn values_per_key(self) -> usize {
        if self == Self::CubicSpline { 3 } else { 1 }
    }
}

/// One animated property of one node: keys (times) and the values at them.
#[derive(Clone, Debug)]
pub struct Channel {
    /// The animated node: an index into [`crate::Scene::nodes`].
    pub node: usize,
    /// What it animates.
    pub path: TargetPath,
    /// How values between keys are found.
    pub interpolation: Interpolation,
    /// Key times in seconds: finite, ≥ 0, strictly increasing, at least one.
    pub times: Vec<f32>,
    /// `times.len() × interpolation.values_per_key()` finite values: xyz for translation and
    /// scale (w unused, 0), a quaternion xyzw for rotation (not necessarily of unit length,
    /// never zero at a key; samples are normalised). For CUBICSPLINE, key `k` is
    /// `[in-tangent, value, out-tangent]` at `3k..3k + 3`.
    pub values: Vec<Vec4>,
}

impl Channel {
    /// The channel's value at `time` seconds, per glTF 2.0 Appendix C: before the first key
    /// and after the last, the value of that key; rotations come back as unit quaternions
    /// (xyzw). A channel whose values do not match its times (only possible when built by
    /// hand) gives the rest-neutral value of its path rather than panicking.
    pub fn sample(&self, time: f32) -> Vec4 {
        self.sample_chunk(time, 0)
    }

    /// Morph-target weights at `time` (for a [`TargetPath::Weights`] channel: its count of
    /// them; otherwise the four components of [`Channel::sample`]).
    pub fn sample_weights(&self, time: f32) -> Vec<f32> {
        let (chunks, count) = match self.path {
            TargetPath::Weights(count) => (self.path.chunks(), count),
            _ => (1, 4),
        };
        let mut out: Vec<f32> = (0..chunks).flat_map(|c| self.sample_chunk(time, c).to_array()).collect();
        out.truncate(count);
        out
    }

    /// Component group `chunk` of the value at `time` (see [`TargetPath::Weights`]).
    fn sample_chunk(&self, time: f32, chunk: usize) -> Vec4 {
        let per_key = self.interpolation.values_per_key();
        let chunks = self.path.chunks();
        let n = self.times.len();
        if n == 0 || self.values.len() != n * per_key * chunks || chunk >= chunks {
            return match self.path {
                TargetPath::Translation | TargetPath::Weights(_) => Vec4::ZERO,
                TargetPath::Rotation => Vec4::W,
                TargetPath::Scale => Vec4::new(1.0, 1.0, 1.0, 0.0),
            };
        }
        let at = |slot: usize| self.values[slot * chunks + chunk];
        let vertex = |k: usize| at(k * per_key + per_key / 2);
        let rotation = self.path == TargetPath::Rotation;
        let (k, raw) = if time.is_nan() || time <= self.times[0] {
            (0, vertex(0))
        } else if time >= self.times[n - 1] {
            (n - 1, vertex(n - 1))
        } else {
            // times[k] ≤ time < times[k + 1]; clamped, should hand-built times not increase.
            let k = self.times.partition_point(|&t| t <= time).saturating_sub(1).min(n - 2);
            let (t0, t1) = (self.times[k], self.times[k + 1]);
            let span = t1 - t0;
            let u = if span > 0.0 { ((time - t0) / span).clamp(0.0, 1.0) } else { 0.0 };
            let value = match self.interpolation {
                Interpolation::Step => vertex(k),
                Interpolation::Linear if rotation => slerp(vertex(k), vertex(k + 1), u),
                Interpolation::Linear => vertex(k).lerp(vertex(k + 1), u),
                Interpolation::CubicSpline => {
                    let out_tangent = at(3 * k + 2);
                    let in_tangent = at(3 * (k + 1));
                    hermite(vertex(k), out_tangent, vertex(k + 1), in_tangent, span, u)
                }
            };
            (k, value)
        };
        if rotation { unit_quaternion(raw).or_else(|| unit_quaternion(vertex(k))).unwrap_or(Vec4::W) } else { raw }
    }

    /// The first and last key times.
    pub fn time_range(&self) -> Option<(f32, f32)> {
        Some((*self.times.first()?, *self.times.last()?))
    }
}

/// `q / |q|`, or `None` for a zero or non-finite `q`.
pub(crate) fn unit_quaternion(q: Vec4) -> Option<Vec4> {
    let length = q.length();
    (length.is_finite() && length > 1e-20).then(|| q / length).filter(|u| u.is_finite())
}

/// glTF 2.0 Appendix C's spherical linear interpolation of two rotations, the shortest way
/// round: `sin(a(1−t))/sin(a)·q₀ + s·sin(at)/sin(a)·q₁` with `a = acos|q₀·q₁|` and `s` the sign
/// of `q₀·q₁`; linear (then normalised) where the two are too close for the division.
fn slerp(q0: Vec4, q1: Vec4, t: f32) -> Vec4 {
    let (Some(q0), Some(q1)) = (unit_quaternion(q0), unit_quaternion(q1)) else { return q0 };
    let dot = q0.dot(q1);
    let (q1, dot) = if dot < 0.0 { (-q1, -dot) } else { (q1, dot) };
    if dot > 0.9995 {
        return q0.lerp(q1, t);
    }
    let a = dot.min(1.0).acos();
    let sin_a = a.sin();
    q0 * ((a * (1.0 - t)).sin() / sin_a) + q1 * ((a * t).sin() / sin_a)
}

/// glTF 2.0 Appendix C's cubic Hermite spline between keys `k` and `k + 1` at `t ∈ [0, 1]`:
/// `(2t³−3t²+1)·v_k + t_d(t³−2t²+t)·b_k + (−2t³+3t²)·v_k₊₁ + t_d(t³−t²)·a_k₊₁`, where `b_k` is
/// key `k`'s out-tangent, `a_k₊₁` key `k + 1`'s in-tangent and `t_d` the time between them.
fn hermite(v0: Vec4, out_tangent: Vec4, v1: Vec4, in_tangent: Vec4, span: f32, t: f32) -> Vec4 {
    let (t2, t3) = (t * t, t * t * t);
    v0 * (2.0 * t3 - 3.0 * t2 + 1.0)
        + out_tangent * (span * (t3 - 2.0 * t2 + t))
        + v1 * (-2.0 * t3 + 3.0 * t2)
        + in_tangent * (span * (t3 - t2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn channel(path: TargetPath, interpolation: Interpolation, times: &[f32], values: &[Vec4]) -> Channel {
        Channel { node: 0, path, interpolation, times: times.to_vec(), values: values.to_vec() }
    }

    #[test]
    fn step_and_linear_and_clamping() {
        let values = [Vec4::ZERO, Vec4::new(2.0, 4.0, 0.0, 0.0)];
        let linear = channel(TargetPath::Translation, Interpolation::Linear, &[1.0, 2.0], &values);
        assert_eq!(linear.sample(1.25), Vec4::new(0.5, 1.0, 0.0, 0.0));
        assert_eq!(linear.sample(0.0), Vec4::ZERO);
        assert_eq!(linear.sample(f32::NAN), Vec4::ZERO);
        assert_eq!(linear.sample(9.0), values[1]);
        let step = channel(TargetPath::Translation, Interpolation::Step, &[1.0, 2.0], &values);
        assert_eq!(step.sample(1.99), Vec4::ZERO);
        assert_eq!(step.sample(2.0), values[1]);
    }

    #[test]
    fn rotations_are_unit_and_take_the_short_way() {
        let half = std::f32::consts::FRAC_1_SQRT_2;
        // 0° and 90° about Z, the second written as its negation (the same rotation).
        let values = [Vec4::new(0.0, 0.0, 0.0, 2.0), Vec4::new(0.0, 0.0, -half, -half)];
        let c = channel(TargetPath::Rotation, Interpolation::Linear, &[0.0, 1.0], &values);
        let q = Quat::from_vec4(c.sample(0.5));
        let angle = q.angle_between(Quat::IDENTITY);
        assert!((angle - std::f32::consts::FRAC_PI_4).abs() < 1e-5, "{angle}");
        assert!((c.sample(0.0).length() - 1.0).abs() < 1e-6);
        // A spline through zero falls back to the key before it rather than to NaN.
        let zero = [Vec4::ZERO, Vec4::W, Vec4::ZERO, Vec4::ZERO, -Vec4::W, Vec4::ZERO];
        let spline = channel(TargetPath::Rotation, Interpolation::CubicSpline, &[0.0, 1.0], &zero);
        assert_eq!(spline.sample(0.5), Vec4::W);
    }

    #[test]
    fn malformed_hand_built_channels_do_not_panic() {
        let c = channel(TargetPath::Scale, Interpolation::CubicSpline, &[0.0, 1.0], &[Vec4::ONE]);
        assert_eq!(c.sample(0.5), Vec4::new(1.0, 1.0, 1.0, 0.0));
        let unsorted = [Vec4::ZERO, Vec4::ONE, Vec4::X];
        let c = channel(TargetPath::Translation, Interpolation::Linear, &[0.0, 5.0, 1.0], &unsorted);
        assert!(c.sample(2.0).is_finite());
    }
}
