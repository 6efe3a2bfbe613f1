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
                let fits = profiles
                    .iter()
                    .filter(|p| serial_fits(p, &port.port_name, usb))
                    .map(|p| p.name.clone())
                    .collect();
                inv.serial.push(SerialPortEntry {
                    path: port.port_name,
                    kind,
                    usb,
                    fits,
                });
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

    #[test]
    fn listing_never_fails() {
        let inv = inventory(&profile::builtin());
        // This machine may have no ports at all; listing must still succeed or say why.
        assert!(inv.serial_error.is_none() || inv.serial.is_empty());
    }
}
