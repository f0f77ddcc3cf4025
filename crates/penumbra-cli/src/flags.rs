//! Value parsers of the command line's flags.

use penumbra::sampling::Distribution;

pub fn parse_distribution(s: &str) -> Result<Distribution, String> {
    Distribution::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Distribution::ALL.iter().map(|d| d.name()).collect();
        format!(
            "unknown distribution `{s}`; valid choices are: {}",
            names.join(", ")
        )
    })
}

pub fn parse_nonneg(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a finite number >= 0")),
    }
}

pub fn parse_positive(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a finite number > 0")),
    }
}
