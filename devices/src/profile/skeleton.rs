//! The skeleton sources of a profile (`"input": {"skeleton": {"protocol": "vmc", …}}`).

use serde::{Deserialize, Serialize};

use crate::DeviceError;

fn default_vmc_listen() -> String {
    format!("127.0.0.1:{}", crate::vmc::DEFAULT_PORT)
}

fn default_bone_timeout_s() -> f64 {
    crate::vmc::DEFAULT_BONE_TIMEOUT_S
}

/// A source of joint poses and its link.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "protocol", deny_unknown_fields)]
pub enum SkeletonProfile {
    /// The VMC protocol: OSC over UDP from a VMC performer ([`crate::vmc`]).
    #[serde(rename = "vmc")]
    Vmc {
        /// The address and port to listen on (default `127.0.0.1:39539`).
        #[serde(default = "default_vmc_listen")]
        listen: String,
        /// How long a bone's last pose stays good without a new one, seconds (default 0.5):
        /// a bone older than this is dropped as if never sent, and the joints through it
        /// are missing ([`crate::vmc`], "Stale bones").
        #[serde(default = "default_bone_timeout_s")]
        bone_timeout_s: f64,
    },
}

impl SkeletonProfile {
    /// The protocol's name in profiles.
    pub fn protocol(&self) -> &'static str {
        match self {
            SkeletonProfile::Vmc { .. } => "vmc",
        }
    }

    /// Where it listens.
    pub fn listen(&self) -> &str {
        match self {
            SkeletonProfile::Vmc { listen, .. } => listen,
        }
    }

    /// How long a bone stays good without a new pose, seconds.
    pub fn bone_timeout_s(&self) -> f64 {
        match self {
            SkeletonProfile::Vmc { bone_timeout_s, .. } => *bone_timeout_s,
        }
    }

    /// Replaces where it listens (`--vmc-listen`).
    pub fn set_listen(&mut self, new: &str) {
        match self {
            SkeletonProfile::Vmc { listen, .. } => *listen = new.to_owned(),
        }
    }

    /// Checks the listening address and the bone timeout; `name` labels errors.
    pub fn validate(&self, name: &str) -> Result<(), DeviceError> {
        crate::vmc::parse_listen(self.listen()).map_err(|e| DeviceError::Profile {
            name: name.to_owned(),
            message: e.to_string(),
        })?;
        let t = self.bone_timeout_s();
        if !(t.is_finite() && t > 0.0 && t <= 60.0) {
            return Err(DeviceError::Profile {
                name: name.to_owned(),
                message: format!(
                    "input.skeleton.bone_timeout_s is {t}; it must be a number of seconds above 0 and at most 60"
                ),
            });
        }
        Ok(())
    }
}
