//! Closed curves as trigonometric series: the series, the planar and
//! space curves, least-squares fitting with its order search, and the
//! ellipse baseline. Depends on `geom`.

pub mod ellipse;
pub mod fit;
pub mod lsq;
pub mod noise;
pub mod order;
pub mod series;
pub mod trig;
