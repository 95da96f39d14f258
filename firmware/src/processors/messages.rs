//! The messages processors exchange (thesis 2.3.2: "exchanging coordinates") and where they go.
use super::template::Template;
use crate::types::Point;


/// A message between processors (thesis 2.3.2: "exchanging coordinates").
// The template variant is large by nature (its pixels travel with it, as on the C40 link);
// it is sent once per lock-on, so the enum's size costs nothing that matters.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Msg {
    /// Watch -> Peripheral: the bounding box of the motion area, inclusive.
    Motion {
        /// Left column.
        xmin: u16,
        /// Right column.
        xmax: u16,
        /// Top row.
        ymin: u16,
        /// Bottom row.
        ymax: u16,
    },
    /// Peripheral -> Foveal: the target is approximately here.
    Approx(Point),
    /// Foveal -> Peripheral: tracked position (an adapting track's: vouched for).
    Tracked(Point),
    /// Adapting Foveal -> Peripheral: the track holds this point, but its first view does not
    /// confirm it; look for the object elsewhere and hand over what is found (issue 38).
    Doubted(Point),
    /// Foveal -> Peripheral: the target was lost near here.
    Lost(Point),
    /// Adapting COOP master -> Peripheral: nothing measured the target, the track begins to
    /// coast and expects it here; search around it and hand over what is found.
    Coasting(Point),
    /// Watch -> others: the template acquired at lock-on.
    Template(Template),
    /// Cooperative Foveal -> master: this frame's result of the second algorithm.
    Result(Option<Point>),
    /// Cooperative master -> second Foveal: acquire the next window around here.
    Follow(Point),
}


/// Where a message goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dest {
    /// The Peripheral processor.
    Peripheral,
    /// The (master) Foveal processor.
    Foveal,
    /// The second cooperative Foveal processor.
    FovealCd,
}
