//! What each driver's result gives the seam ([`RunOutcome`] for the results the protocols'
//! runs are made of): the observables to compare with measured data, the error that ended
//! the run, and whether the layout did not stand.

use super::contract::RunOutcome;
use super::observed::Observed;
use crate::limit::{LimitError, LimitResult};
use crate::loading::lateral::{LateralError, LateralResult};
use crate::loading::lateral_nscd::LateralLimit;
use crate::loading::shake::{ShakeError, ShakeResult};
use crate::loading::tilt::{TiltError, TiltResult};

/// The tilting table's path (penalty DEM, nscd, rolled by hand): its collapse angle, the
/// top displacements at every stable tilt and the mechanism.
impl RunOutcome for Result<TiltResult, TiltError> {
    fn observed(&self) -> Option<Observed> {
        self.as_ref().ok().map(Observed::of_tilt)
    }
    fn error(&self) -> Option<String> {
        self.as_ref().err().map(ToString::to_string)
    }
    fn does_not_stand(&self) -> bool {
        matches!(self, Err(TiltError::DoesNotStand(_)))
    }
}

/// The static lateral load by the penalty DEM: the top displacements under the load.
impl RunOutcome for Result<LateralResult, LateralError> {
    fn observed(&self) -> Option<Observed> {
        self.as_ref().ok().map(Observed::of_lateral)
    }
    fn error(&self) -> Option<String> {
        self.as_ref().err().map(ToString::to_string)
    }
    fn does_not_stand(&self) -> bool {
        matches!(self, Err(LateralError::DoesNotStand(_)))
    }
}

/// Limit analysis: a load multiplier, nothing to compare with measured data.
impl RunOutcome for Result<LimitResult, LimitError> {
    fn observed(&self) -> Option<Observed> {
        None
    }
    fn error(&self) -> Option<String> {
        self.as_ref().err().map(ToString::to_string)
    }
    fn does_not_stand(&self) -> bool {
        matches!(
            self,
            Err(LimitError::Untouched { .. }
                | LimitError::Floating { .. }
                | LimitError::Infeasible { .. }
                | LimitError::DoesNotStand { .. })
        )
    }
}

/// The rigid pushover by nscd: a load multiplier, nothing to compare with measured data.
impl RunOutcome for Result<LateralLimit, TiltError> {
    fn observed(&self) -> Option<Observed> {
        None
    }
    fn error(&self) -> Option<String> {
        self.as_ref().err().map(ToString::to_string)
    }
    fn does_not_stand(&self) -> bool {
        matches!(self, Err(TiltError::DoesNotStand(_)))
    }
}

/// The shaking table: a time history, nothing to compare with measured data.
impl RunOutcome for Result<ShakeResult, ShakeError> {
    fn observed(&self) -> Option<Observed> {
        None
    }
    fn error(&self) -> Option<String> {
        self.as_ref().err().map(ToString::to_string)
    }
    fn does_not_stand(&self) -> bool {
        matches!(self, Err(ShakeError::DoesNotStand(_)))
    }
}
