//! How far an image is from another: the metrics of `mrshade compare` and `mrshade eval`, over
//! the whole image or over a mask, and the evaluation report (Markdown, JSON, HTML), with its
//! part for posed image sequences.

mod chart;
pub mod metrics;
pub mod report;
pub mod sequence;
