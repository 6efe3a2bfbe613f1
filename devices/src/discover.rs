//! What is plugged in: serial ports and USB HID devices, and which profiles fit each.
//!
//! A profile fits a serial port when one of its serial devices names that port (compared after
//! resolving symbolic links) or declares the USB ids of the port's adapter; it fits a HID
//! device when its HID glove's USB ids match (vendor, and product when given).

use std::path::Path;

use crate::profile::{GloveProfile, Profile, UsbMatch};

/// A serial port that is present.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SerialPortEntry {
    /// Device path.
    pub path: String,
    /// What kind of port it is (USB adapter with its ids and product, PCI, Bluetooth, unknown).
    pub kind: String,
    /// USB vendor and product ids, for USB adapters.
    pub usb: Option<(u16, u16)>,
    /// Names of the profiles that fit.
    pub fits: Vec<String>,
}

/// A USB HID device that is present.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HidEntry {
    /// Platform path of the device.
    pub path: String,
    /// Vendor id.
    pub vid: u16,
    /// Product id.
    pub pid: u16,
    /// Manufacturer and product strings, as reported.
    pub product: String,
    /// Names of the profiles that fit.
    pub fits: Vec<String>,
}

/// Everything found.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Inventory {
    /// Serial ports.
    pub serial: Vec<SerialPortEntry>,
    /// Why serial ports could not be listed, if they could not.
    pub serial_error: Option<String>,
    /// HID devices.
    pub hid: Vec<HidEntry>,
    /// Why HID devices could not be listed, if they could not.
    pub hid_error: Option<String>,
}

fn same_path(a: &str, b: &str) -> bool {
    if a == b {
        return true;
    }
    match (Path::new(a).canonicalize(), Path::new(b).canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// The serial ports and USB ids a profile's devices use.
fn serial_devices(p: &Profile) -> Vec<(String, Option<UsbMatch>)> {
    let mut v = Vec::new();
    if let Some(g) = p.glove()
        && let Some(port) = g.port()
    {
        v.push((port.to_string(), g.usb()));
    }
    if let Some(t) = p.tracker() {
        v.push((t.port().to_string(), t.usb()));
    }
    v
}

/// Whether a profile fits a serial port.
pub fn serial_fits(profile: &Profile, path: &str, usb: Option<(u16, u16)>) -> bool {
    serial_devices(profile).iter().any(|(port, m)| {
        same_path(port, path)
            || matches!((m, usb), (Some(m), Some((vid, pid))) if m.matches(vid, pid))
    })
}

/// Whether a profile fits a HID device.
pub fn hid_fits(profile: &Profile, vid: u16, pid: u16) -> bool {
    matches!(profile.glove(), Some(GloveProfile::FiveDtUltraUsb { usb, .. }) if usb.matches(vid, pid))
}

/// The inventory's entry for a serial port that is present: its path, kind and USB ids, and
/// the names of the `profiles` that fit it ([`serial_fits`]).
fn serial_entry(
    path: String,
    kind: String,
    usb: Option<(u16, u16)>,
    profiles: &[Profile],
) -> SerialPortEntry {
    let fits = profiles
        .iter()
        .filter(|p| serial_fits(p, &path, usb))
        .map(|p| p.name.clone())
        .collect();
    SerialPortEntry {
        path,
        kind,
        usb,
        fits,
    }
}

/// Lists serial ports and HID devices and matches them against `profiles`. Listing failures
/// are reported in the inventory, not as errors: an empty machine is a normal answer.
pub fn inventory(profiles: &[Profile]) -> Inventory {
    let mut inv = Inventory::default();
    match serialport::available_ports() {
        Ok(ports) => {
            for port in ports {
                let (kind, usb) = match &port.port_type {
                    serialport::SerialPortType::UsbPort(u) => {
                        let product = [u.manufacturer.as_deref(), u.product.as_deref()]
                            .into_iter()
                            .flatten()
                            .collect::<Vec<_>>()
                            .join(" ");
                        (
                            format!("USB {:04x}:{:04x} {product}", u.vid, u.pid)
                                .trim_end()
                                .to_string(),
                            Some((u.vid, u.pid)),
                        )
                    }
                    serialport::SerialPortType::PciPort => ("PCI".to_string(), None),
                    serialport::SerialPortType::BluetoothPort => ("Bluetooth".to_string(), None),
                    serialport::SerialPortType::Unknown => ("unknown".to_string(), None),
                };
                inv.serial
                    .push(serial_entry(port.port_name, kind, usb, profiles));
            }
        }
        Err(e) => inv.serial_error = Some(e.to_string()),
    }
    match hidapi::HidApi::new() {
        Ok(api) => {
            for d in api.device_list() {
                let (vid, pid) = (d.vendor_id(), d.product_id());
                let product = [d.manufacturer_string(), d.product_string()]
                    .into_iter()
                    .flatten()
                    .collect::<Vec<_>>()
                    .join(" ");
                let fits = profiles
                    .iter()
                    .filter(|p| hid_fits(p, vid, pid))
                    .map(|p| p.name.clone())
                    .collect();
                inv.hid.push(HidEntry {
                    path: d.path().to_string_lossy().into_owned(),
                    vid,
                    pid,
                    product,
                    fits,
                });
            }
        }
        Err(e) => inv.hid_error = Some(e.to_string()),
    }
    inv
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile;

    #[test]
    fn profiles_fit_by_port_and_by_usb_ids() {
        let cg = profile::resolve("cyberglove2-18").unwrap();
        assert!(serial_fits(&cg, "/dev/ttyUSB0", None));
        assert!(!serial_fits(&cg, "/dev/ttyUSB1", None));
        let ultra = profile::resolve("5dt-ultra14-usb").unwrap();
        assert!(hid_fits(&ultra, 0x5D70, 0x0100));
        assert!(!hid_fits(&ultra, 0x046D, 0x0100));
        assert!(!hid_fits(&cg, 0x5D70, 0x0100));
    }

    #[cfg(unix)]
    #[test]
    fn a_listed_port_is_matched_to_the_profiles_that_name_it_or_its_usb_ids() {
        let builtin = profile::builtin();
        // A port a profile names, behind a symbolic link: the link is resolved.
        let dir = std::env::temp_dir().join(format!("nendo-discover-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("ttyFAKE0");
        std::fs::write(&target, b"").unwrap();
        let link = dir.join("glove");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let mut cg = profile::resolve("cyberglove2-18").unwrap();
        cg.name = "linked-glove".into();
        let crate::profile::Input::Devices {
            glove: Some(glove), ..
        } = &mut cg.input
        else {
            panic!("cyberglove2-18 has a glove")
        };
        glove.set_port(&link.to_string_lossy());
        let profiles: Vec<Profile> = builtin.iter().cloned().chain([cg]).collect();
        let entry = serial_entry(
            target.to_string_lossy().into_owned(),
            "unknown".into(),
            None,
            &profiles,
        );
        assert_eq!(entry.fits, ["linked-glove"], "{entry:?}");
        // A port no profile uses fits none.
        let other = serial_entry("/dev/ttyS7".into(), "PCI".into(), None, &profiles);
        assert!(other.fits.is_empty(), "{other:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn listing_the_machine_matches_what_it_finds_or_says_why_not() {
        let profiles = profile::builtin();
        let inv = inventory(&profiles);
        // This machine may have no ports at all; listing must still succeed or say why, and
        // every port found is matched by the same rule.
        assert!(inv.serial_error.is_none() || inv.serial.is_empty());
        for e in &inv.serial {
            let want: Vec<String> = profiles
                .iter()
                .filter(|p| serial_fits(p, &e.path, e.usb))
                .map(|p| p.name.clone())
                .collect();
            assert_eq!(e.fits, want, "{e:?}");
        }
    }
}
