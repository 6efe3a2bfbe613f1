//! The skeleton sources of a profile (`"input": {"skeleton": {"protocol": "vmc", …}}`).

use serde::{Deserialize, Serialize};

use crate::DeviceError;

fn default_vmc_listen() -> String {
    format!("127.0.0.1:{}", crate::vmc::DEFAULT_PORT)
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
            SkeletonProfile::Vmc { listen } => listen,
        }
    }

    /// Replaces where it listens (`--vmc-listen`).
    pub fn set_listen(&mut self, new: &str) {
        match self {
            SkeletonProfile::Vmc { listen } => *listen = new.to_owned(),
        }
    }

    /// Checks the listening address; `name` labels errors.
    pub fn validate(&self, name: &str) -> Result<(), DeviceError> {
        crate::vmc::parse_listen(self.listen()).map_err(|e| DeviceError::Profile {
            name: name.to_owned(),
            message: e.to_string(),
        })?;
        Ok(())
    }
}
