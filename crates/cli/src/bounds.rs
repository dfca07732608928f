//! Ranges of the options that size work or memory (point counts, spacings,
//! orders, resolutions), checked while the arguments are parsed: a value
//! outside is exit 2 naming the option and its range, before anything is
//! allocated.

use trigbody_core::Real;

/// A whole number in `lo..=hi` (a `clap` value parser), of any integer
/// type (counts, pixel sizes).
pub fn count_in<T>(
    lo: T,
    hi: T,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display + Copy + Send + Sync + 'static,
{
    move |s: &str| match s.trim().parse::<T>() {
        Ok(n) if lo <= n && n <= hi => Ok(n),
        _ => Err(format!("must be a whole number in {lo}..={hi}")),
    }
}

/// A number in `[lo, hi]`; NaN and infinities are refused.
pub fn real_in(
    lo: Real,
    hi: Real,
) -> impl Fn(&str) -> Result<Real, String> + Clone + Send + Sync + 'static {
    move |s: &str| match s.trim().parse::<Real>() {
        Ok(x) if x >= lo && x <= hi => Ok(x),
        _ => Err(format!("must be a number in [{lo}, {hi}]")),
    }
}

/// A finite number above zero.
pub fn positive(s: &str) -> Result<Real, String> {
    match s.trim().parse::<Real>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err("must be a finite number above 0".into()),
    }
}

/// A fit tolerance `--ea`: a finite number above 0, refused with the
/// library's own message (the Python package raises the same text).
pub fn tolerance_ea(s: &str) -> Result<Real, String> {
    tolerance("ea", s)
}

/// A fit tolerance `--em` (see [`tolerance_ea`]).
pub fn tolerance_em(s: &str) -> Result<Real, String> {
    tolerance("em", s)
}

fn tolerance(name: &'static str, s: &str) -> Result<Real, String> {
    let value = s.trim().parse::<Real>().unwrap_or(Real::NAN);
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(trigbody_core::FitError::BadTolerance { name, value }.to_string())
    }
}

/// A finite number, zero or above.
pub fn non_negative(s: &str) -> Result<Real, String> {
    match s.trim().parse::<Real>() {
        Ok(x) if x >= 0.0 && x.is_finite() => Ok(x),
        _ => Err("must be a finite number, 0 or above".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_outside_the_range_are_refused_with_the_range() {
        let c = count_in(1, 10);
        assert_eq!(c("10"), Ok(10));
        assert_eq!(c("0"), Err("must be a whole number in 1..=10".into()));
        assert!(c("-1").is_err() && c("1e3").is_err());
        let r = real_in(0.002, 0.2);
        assert_eq!(r("0.012"), Ok(0.012));
        assert!(r("1e-6").unwrap_err().contains("[0.002, 0.2]"));
        assert!(r("NaN").is_err());
        assert!(positive("0").is_err() && positive("inf").is_err());
        assert_eq!(non_negative("0"), Ok(0.0));
        assert!(non_negative("-5").is_err());
        assert_eq!(
            count_in(64u32, 4096)("0").unwrap_err(),
            "must be a whole number in 64..=4096"
        );
    }
}
