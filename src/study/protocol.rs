//! A study's protocol with its parameters ([`StudyProtocol`]): the kind the file names and
//! its table together, so that the resolver, the run, the report and the figures each
//! match on one value.

use super::motions::ShakeStudy;
use super::spec::ProtocolKind;
use crate::loading::lateral::LateralParams;
use crate::loading::support::Loading;
use crate::loading::tilt::TiltParams;
use crate::protocol::Protocol;

/// A study's protocol with its parameters: the kind and its table together, so that every
/// consumer matches on one value (a new protocol is pointed to by the compiler at each).
#[derive(Debug, Clone)]
pub enum StudyProtocol {
    /// The tilting table (`protocol = "tilt"`, its `[tilt]` table).
    Tilt(TiltParams),
    /// The static lateral load, or its pushover (`protocol = "lateral"`, `[lateral]`).
    Lateral(LateralParams),
    /// The shaking table (`protocol = "shake"`, `[shake]`): its parameters, motions and
    /// levels.
    Shake(ShakeStudy),
}

impl StudyProtocol {
    /// Its kind, as the study file names it.
    pub fn kind(&self) -> ProtocolKind {
        match self {
            StudyProtocol::Tilt(_) => ProtocolKind::Tilt,
            StudyProtocol::Lateral(_) => ProtocolKind::Lateral,
            StudyProtocol::Shake(_) => ProtocolKind::Shake,
        }
    }

    /// Its name in study files (`protocol = "..."`).
    pub fn name(&self) -> &'static str {
        match self {
            StudyProtocol::Tilt(_) => "tilt",
            StudyProtocol::Lateral(_) => "lateral",
            StudyProtocol::Shake(_) => "shake",
        }
    }

    /// Its row of the compatibility table ([`crate::loading::support`]), with the variant
    /// its table chooses (`tilt.by_hand`, `lateral.pushover`).
    pub fn loading_kind(&self) -> Loading {
        match self {
            StudyProtocol::Tilt(t) => Protocol::Tilt(*t).kind(),
            StudyProtocol::Lateral(l) => Protocol::Lateral(*l).kind(),
            StudyProtocol::Shake(_) => Loading::Shake,
        }
    }

    /// The tilting table's parameters, for a tilting-table study.
    pub fn tilt(&self) -> Option<&TiltParams> {
        match self {
            StudyProtocol::Tilt(t) => Some(t),
            StudyProtocol::Lateral(_) | StudyProtocol::Shake(_) => None,
        }
    }

    /// The lateral load's parameters, for a lateral study.
    pub fn lateral(&self) -> Option<&LateralParams> {
        match self {
            StudyProtocol::Lateral(l) => Some(l),
            StudyProtocol::Tilt(_) | StudyProtocol::Shake(_) => None,
        }
    }

    /// The shaking table's parameters, motions and levels, for a shaking study.
    pub fn shake(&self) -> Option<&ShakeStudy> {
        match self {
            StudyProtocol::Shake(s) => Some(s),
            StudyProtocol::Tilt(_) | StudyProtocol::Lateral(_) => None,
        }
    }

    /// Whether it pushes the lateral load over to collapse (`lateral.pushover`).
    pub fn pushover(&self) -> bool {
        self.lateral().is_some_and(|l| l.pushover)
    }
}
