//! Query parameters: the fit options under the command line's names (`tolerance`,
//! `continuity`, `alpha`, `alpha_range`, `corner_angle`, `keep_hooks`, `close`, `lcg`) and each export's
//! own (`layers`, `accuracy`, `size`), checked as `kansei fit` checks its options.

use crate::lac::AlphaChoice;
use crate::pipeline::PipelineOptions;
use crate::stroke::Units;

use super::error::ApiError;

/// The fit options every fitting endpoint takes.
pub const FIT_PARAMS: [&str; 8] = [
    "tolerance",
    "continuity",
    "alpha",
    "alpha_range",
    "corner_angle",
    "keep_hooks",
    "close",
    "lcg",
];

/// The SVG layers `layers` may name (as `kansei fit --svg-layers`).
pub const SVG_LAYERS: [&str; 4] = crate::export::SvgLayers::NAMES;

/// The PNG layers `layers` may name (as `kansei fit --png-layers`).
pub const PNG_LAYERS: [&str; 10] = crate::render::OVERLAY_NAMES;

/// The default PNG size, as `kansei fit --size`.
pub const DEFAULT_PNG_SIZE: (u32, u32) = crate::export::DEFAULT_PNG_SIZE;

/// A request's query parameters, in order, each name at most once.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Params {
    pairs: Vec<(String, String)>,
}

impl Params {
    /// Parses a query string (`None`: no query), refusing names outside `allowed` and names
    /// given twice.
    pub fn parse(query: Option<&str>, allowed: &[&str]) -> Result<Self, ApiError> {
        let query = query.unwrap_or("");
        let uri: axum::http::Uri = format!("/?{query}")
            .parse()
            .map_err(|e| ApiError::bad_request(format!("the query string: {e}")))?;
        let axum::extract::Query(pairs) =
            axum::extract::Query::<Vec<(String, String)>>::try_from_uri(&uri)
                .map_err(|e| ApiError::bad_request(e.body_text()))?;
        for (i, (name, _)) in pairs.iter().enumerate() {
            if !allowed.contains(&name.as_str()) {
                return Err(ApiError::bad_request(format!(
                    "unknown query parameter {name:?}; this endpoint takes {}",
                    allowed.join(", ")
                )));
            }
            if pairs[..i].iter().any(|(n, _)| n == name) {
                return Err(ApiError::bad_request(format!(
                    "query parameter {name:?} is given twice"
                )));
            }
        }
        Ok(Params { pairs })
    }

    /// The value of `name`, if given.
    pub fn get(&self, name: &str) -> Option<&str> {
        self.pairs
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    fn number(&self, name: &str) -> Result<Option<f64>, ApiError> {
        self.get(name)
            .map(|v| {
                v.trim().parse::<f64>().map_err(|e| {
                    ApiError::bad_request(format!("{name}: {v:?} is not a number ({e})"))
                })
            })
            .transpose()
    }

    fn flag(&self, name: &str) -> Result<bool, ApiError> {
        match self.get(name) {
            None | Some("false") | Some("0") => Ok(false),
            Some("") | Some("true") | Some("1") => Ok(true),
            Some(v) => Err(ApiError::bad_request(format!(
                "{name} must be true or false, got {v:?}"
            ))),
        }
    }

    /// The pipeline options, as `kansei fit` makes them from the same options.
    pub fn pipeline_options(&self) -> Result<PipelineOptions, ApiError> {
        let mut options = PipelineOptions::default();
        if let Some(t) = self.number("tolerance")? {
            if !(t.is_finite() && t > 0.0) {
                return Err(ApiError::bad_request(format!(
                    "tolerance must be a positive number, got {t}"
                )));
            }
            options.tolerance = Some(t);
        }
        if let Some(c) = self.get("continuity") {
            options.chain.continuity = c.parse().map_err(ApiError::bad_request)?;
        }
        if let Some(a) = self.number("corner_angle")? {
            if !a.is_finite() {
                return Err(ApiError::bad_request(format!(
                    "corner_angle must be a finite number of degrees, got {a}"
                )));
            }
            options.corner_angle = a;
        }
        options.keep_hooks = self.flag("keep_hooks")?;
        if let Some(close) = self.get("close") {
            let close: crate::closure::Close = close.parse().map_err(ApiError::bad_request)?;
            options.close = close == crate::closure::Close::Auto;
        }
        match (self.number("alpha")?, self.get("alpha_range")) {
            (Some(_), Some(_)) => {
                return Err(ApiError::bad_request(
                    "alpha and alpha_range cannot be used together",
                ));
            }
            (Some(alpha), None) => {
                if !alpha.is_finite() {
                    return Err(ApiError::bad_request(format!(
                        "alpha must be a finite number, got {alpha}"
                    )));
                }
                options.chain.alpha = AlphaChoice::Fixed(alpha);
            }
            (None, Some(range)) => {
                let (min, max) = crate::lac::parse_alpha_range(range)
                    .map_err(|e| ApiError::bad_request(format!("alpha_range: {e}")))?;
                options.chain.alpha = AlphaChoice::Range { min, max };
            }
            (None, None) => {}
        }
        Ok(options)
    }

    /// `lcg`: add each segment's logarithmic curvature graphs to the document.
    pub fn lcg(&self) -> Result<bool, ApiError> {
        self.flag("lcg")
    }

    /// `accuracy`: the exports' largest distance from the exact chain (default: a tenth of the
    /// tolerance).
    pub fn accuracy(&self) -> Result<Option<f64>, ApiError> {
        let a = self.number("accuracy")?;
        if let Some(a) = a
            && !(a.is_finite() && a > 0.0)
        {
            return Err(ApiError::bad_request(format!(
                "accuracy must be a positive number, got {a}"
            )));
        }
        Ok(a)
    }

    /// `layers`, comma-separated names out of `known` (`None`: not given).
    pub fn layers(&self, known: &[&str]) -> Result<Option<Vec<String>>, ApiError> {
        let Some(list) = self.get("layers") else {
            return Ok(None);
        };
        let names: Vec<String> = list
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect();
        if let Some(bad) = names.iter().find(|n| !known.contains(&n.as_str())) {
            return Err(ApiError::bad_request(format!(
                "layers: unknown layer {bad:?}; known layers are {}",
                known.join(", ")
            )));
        }
        Ok(Some(names))
    }

    /// `size=WIDTHxHEIGHT` of the PNG (default [`DEFAULT_PNG_SIZE`]); the render checks the
    /// range.
    pub fn size(&self) -> Result<(u32, u32), ApiError> {
        let Some(text) = self.get("size") else {
            return Ok(DEFAULT_PNG_SIZE);
        };
        let (w, h) = text
            .split_once(['x', 'X', '×'])
            .ok_or_else(|| ApiError::bad_request(format!("size: expected WxH, got {text:?}")))?;
        let parse = |x: &str| {
            x.trim()
                .parse::<u32>()
                .map_err(|e| ApiError::bad_request(format!("size: {x:?}: {e}")))
        };
        Ok((parse(w)?, parse(h)?))
    }

    /// `units` of the streamed samples (default px).
    pub fn units(&self) -> Result<Units, ApiError> {
        match self.get("units") {
            None | Some("px") => Ok(Units::Px),
            Some("mm") => Ok(Units::Mm),
            Some("device") => Ok(Units::Device),
            Some(u) => Err(ApiError::bad_request(format!(
                "units must be px, mm or device, got {u:?}"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(query: &str) -> Result<PipelineOptions, ApiError> {
        Params::parse(Some(query), &FIT_PARAMS)?.pipeline_options()
    }

    #[test]
    fn the_command_line_options_by_name() {
        let o = fit("tolerance=0.25&alpha=-1&corner_angle=45&keep_hooks=true&continuity=g1")
            .expect("valid");
        assert_eq!(o.tolerance, Some(0.25));
        assert_eq!(o.chain.alpha, AlphaChoice::Fixed(-1.0));
        assert_eq!(o.corner_angle, 45.0);
        assert!(o.keep_hooks);
        let o = fit("alpha_range=-2:1.5").expect("valid");
        assert_eq!(
            o.chain.alpha,
            AlphaChoice::Range {
                min: -2.0,
                max: 1.5
            }
        );
        assert_eq!(fit("").expect("valid"), PipelineOptions::default());
    }

    #[test]
    fn refusals_name_the_parameter() {
        for (query, words) in [
            ("tolerance=0", "tolerance must be a positive number"),
            ("tolerance=abc", "tolerance: \"abc\" is not a number"),
            ("continuity=g3", "continuity must be one of g1, g2, c3"),
            ("alpha=1&alpha_range=0:1", "cannot be used together"),
            ("alpha_range=2:1", "not a finite interval"),
            ("alpha=inf", "alpha must be a finite number"),
            ("keep_hooks=maybe", "keep_hooks must be true or false"),
            ("tolerence=1", "unknown query parameter \"tolerence\""),
            ("alpha=1&alpha=2", "given twice"),
        ] {
            let e = fit(query).expect_err(query);
            assert_eq!(e.status, axum::http::StatusCode::BAD_REQUEST);
            assert!(e.message.contains(words), "{query}: {}", e.message);
        }
    }
}
