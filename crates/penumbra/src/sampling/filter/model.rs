//! What every pixel filter implements ([`FilterModel`]), and the
//! parameters and errors they are built from.

/// The cells of a filter's table: 1024, or 512 per lobe of a Lanczos
/// filter of more than 2 (whose profile has a lobe per pixel of its
/// radius; the others' shapes do not change with their size).
pub(super) const CELLS: usize = 1024;

/// What every pixel filter answers (see the [module docs](super)).
pub trait FilterModel: Copy {
    /// The name users write (the serde name too).
    const NAME: &'static str;

    /// The names of the parameters it takes (see [`FilterParams`]).
    const PARAMS: &'static [&'static str] = &[];

    /// It is sampled by the analytic inverse of its distribution
    /// ([`warp`](Self::warp)); the others through a table of it.
    const ANALYTIC: bool = false;

    /// The filter of `params` (the missing ones at their defaults, the
    /// others not its own already refused), or why not.
    fn build(params: &FilterParams) -> Result<Self, FilterError>;

    /// How far from the pixel's centre a sample may land, in pixels.
    fn radius(self) -> f32;

    /// The profile along one axis (not normalised; 0 beyond the radius).
    fn eval(self, x: f64) -> f64;

    /// For an [analytic](Self::ANALYTIC) filter, the offset of the film
    /// point coordinate `p` in `[-1/2, 1/2]`, increasing in `p`; `None`
    /// for the others.
    #[inline]
    fn warp(self, _p: f32) -> Option<f32> {
        None
    }

    /// The cells of its table.
    fn cells(self) -> usize {
        CELLS
    }
}

/// The parameters given to a filter; a missing one takes its default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilterParams {
    pub radius: Option<f32>,
    pub stddev: Option<f32>,
    pub b: Option<f32>,
    pub c: Option<f32>,
    pub lobes: Option<i64>,
}

impl FilterParams {
    /// The parameters given, by their names ([`Filter::params`](super::Filter::params)).
    pub fn given(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        let mut add = |name, given: bool| {
            if given {
                out.push(name);
            }
        };
        add("radius", self.radius.is_some());
        add("stddev", self.stddev.is_some());
        add("B", self.b.is_some());
        add("C", self.c.is_some());
        add("lobes", self.lobes.is_some());
        out
    }
}

/// Why a filter's parameters were refused: the parameter (by its name in
/// [`Filter::params`](super::Filter::params)) and what is wrong with it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FilterError {
    pub param: &'static str,
    pub message: String,
}

impl FilterError {
    /// The error of parameter `param`, for a message of why.
    pub(super) fn of(param: &'static str) -> impl Fn(String) -> FilterError {
        move |message| FilterError { param, message }
    }
}
