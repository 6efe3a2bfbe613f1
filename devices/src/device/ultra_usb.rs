//! The 5DT Data Glove Ultra on USB HID (hidapi): its backend.

#[allow(unused_imports)] // The parent's imports, as the code had them there.
use super::*;

// 5DT Ultra over USB HID

/// The 5DT Data Glove Ultra on USB HID (hidapi, Linux hidraw without libudev headers).
///
/// On every start the glove's product id says which model it is ([`fivedt::UltraModel`]): the
/// profile's calibration is fitted to it ([`fivedt::UltraModel::fit_calibration`]: a 5-sensor
/// glove is read at its five values only, a table that maps none of them is refused), and a
/// glove for the other hand than the profile's is reported in [`Glove::warnings`].
pub struct UltraUsbGlove {
    usb: crate::profile::UsbMatch,
    report_id: bool,
    /// The profile's table, one entry per report value.
    calibration: Vec<SensorCalibration>,
    /// The profile's hand, checked against the glove's.
    hand: Option<Side>,
    /// The table in force: the profile's, fitted to the model found at the last start.
    active: Vec<SensorCalibration>,
    model: Option<fivedt::UltraModel>,
    warnings: Vec<String>,
    device: Option<hidapi::HidDevice>,
    stats: DeviceStats,
    /// When the last report arrived.
    arrived: Option<std::time::Instant>,
}

impl UltraUsbGlove {
    /// A glove backend for these USB ids and this calibration table (one entry per report
    /// value), checked against `hand` when given. Not yet started.
    pub fn new(
        usb: crate::profile::UsbMatch,
        report_id: bool,
        calibration: Vec<SensorCalibration>,
        hand: Option<Side>,
    ) -> Self {
        UltraUsbGlove {
            usb,
            report_id,
            active: calibration.clone(),
            calibration,
            hand,
            model: None,
            warnings: Vec::new(),
            device: None,
            stats: DeviceStats::default(),
            arrived: None,
        }
    }

    fn hid(e: hidapi::HidError) -> DeviceError {
        DeviceError::Hid(e.to_string())
    }

    /// Takes in the product id of the glove found: fits the calibration to its model and
    /// records the warnings. A table that fits nothing is an error, and the glove is not used.
    pub fn configure(&mut self, pid: u16) -> Result<fivedt::UltraModel, DeviceError> {
        let model = fivedt::UltraModel::from_product_id(pid);
        let fit = model.fit_calibration(pid, &self.calibration, self.hand)?;
        self.active = fit.calibration;
        self.warnings = fit.warnings;
        self.model = Some(model);
        Ok(model)
    }

    /// The model found at the last start.
    pub fn model(&self) -> Option<fivedt::UltraModel> {
        self.model
    }

    /// Decodes one input report into a sample with the calibration in force, counting it.
    pub fn decode_report(&mut self, report: &[u8], out: &mut Vec<GloveSample>) {
        let n = report.len() as u64;
        self.stats.decode.bytes_in += n;
        match fivedt::decode_ultra_report(report, self.report_id) {
            Ok(values)
                if values
                    .iter()
                    .any(|v| v.unsigned_abs() > fivedt::ULTRA_FULL_SCALE) =>
            {
                // Beyond the sensor's full scale: corrupt, dropped and counted.
                self.stats.decode.records += 1;
                self.stats.decode.record_bytes += n;
                self.stats.invalid += 1;
            }
            Ok(values) => {
                self.stats.decode.records += 1;
                self.stats.decode.record_bytes += n;
                let raw = values.map(f64::from);
                match calibrate(&self.active, &raw) {
                    Ok(angles) => out.push(GloveSample {
                        angles,
                        switch: None,
                    }),
                    Err(_) => self.stats.invalid += 1,
                }
            }
            Err(_) => {
                self.stats.decode.rejected += 1;
                self.stats.decode.skipped_bytes += n;
            }
        }
    }
}

impl Glove for UltraUsbGlove {
    fn describe(&self) -> String {
        match self.usb.pid {
            Some(pid) => format!("5DT Data Glove Ultra (USB {:04x}:{pid:04x})", self.usb.vid),
            None => format!("5DT Data Glove Ultra (USB vendor {:04x})", self.usb.vid),
        }
    }

    fn joints(&self) -> Vec<Joint> {
        joints_of(&self.active)
    }

    fn start(&mut self) -> Result<(), DeviceError> {
        self.device = None;
        let api = hidapi::HidApi::new().map_err(Self::hid)?;
        let info = api
            .device_list()
            .find(|d| self.usb.matches(d.vendor_id(), d.product_id()))
            .ok_or_else(|| {
                DeviceError::Hid(format!("no HID device matches {}", self.describe()))
            })?;
        self.configure(info.product_id())?;
        let device = info.open_device(&api).map_err(Self::hid)?;
        self.device = Some(device);
        self.stats.starts += 1;
        Ok(())
    }

    fn read(&mut self, timeout: Duration, out: &mut Vec<GloveSample>) -> Result<(), DeviceError> {
        let Some(device) = self.device.as_ref() else {
            return Err(DeviceError::Hid("not started".into()));
        };
        let mut buf = [0u8; fivedt::ULTRA_REPORT_LEN + 1];
        let n = device
            .read_timeout(&mut buf, timeout.as_millis().min(i32::MAX as u128) as i32)
            .map_err(Self::hid)?;
        if n > 0 {
            self.arrived = Some(std::time::Instant::now());
            self.decode_report(&buf[..n.min(buf.len())], out);
        }
        Ok(())
    }

    fn stop(&mut self) {
        self.device = None;
    }

    fn stats(&self) -> DeviceStats {
        self.stats
    }

    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    fn arrived(&self) -> Option<std::time::Instant> {
        self.arrived
    }
}
