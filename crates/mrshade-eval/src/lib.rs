//! How far an image is from another: the metrics of `mrshade compare` (and of the evaluation
//! to come), over the whole image or over a mask.

pub mod metrics;
