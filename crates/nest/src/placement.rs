//! Where the irregular nester puts a part, in the jagua-rs frame: shared by the search
//! ([`crate::irregular`]) and the compression that finishes it ([`crate::compress`]).

/// One part placed in the jagua-rs frame: its centred, inflated shape turned by rotation `rot`
/// and moved by `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Placement {
    pub(crate) part: usize,
    pub(crate) rot: usize,
    pub(crate) t: (f32, f32),
}

/// A whole layout, independent of any `BPProblem`: what workers exchange.
pub(crate) type Sheets = Vec<Vec<Placement>>;
