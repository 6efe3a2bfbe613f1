//! Tests of [`super`].

use super::*;
use crate::profile::{self, UsbMatch};

fn ultra_14_table() -> Vec<SensorCalibration> {
    profile::resolve("5dt-ultra14-usb")
        .unwrap()
        .glove()
        .unwrap()
        .calibration()
        .to_vec()
}

#[test]
fn an_ultra_glove_is_read_with_the_table_of_the_model_its_product_id_names() {
    let usb = UsbMatch {
        vid: fivedt::ULTRA_VENDOR_ID,
        pid: None,
    };
    let mut glove = UltraUsbGlove::new(usb, false, ultra_14_table(), Some(Side::Right));
    assert_eq!(glove.joints().len(), 14);
    // A 5-sensor right-hand glove: only values 0, 3, 6, 9, 12 are read.
    let model = glove.configure(0x5D10).unwrap();
    assert!(model.five_sensors && !model.left_hand);
    assert_eq!(glove.joints(), fivedt::JOINTS_5);
    assert_eq!(glove.warnings().len(), 1);
    let values: [i16; 16] = std::array::from_fn(|i| 100 * (i as i16 + 1));
    let mut out = Vec::new();
    glove.decode_report(&fivedt::encode_ultra_report(&values, None), &mut out);
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].angles.len(), 5);
    let table = ultra_14_table();
    for (&slot, &joint) in fivedt::ULTRA_5_SENSOR_SLOTS.iter().zip(&fivedt::JOINTS_5) {
        let want = f64::from(values[slot]) * table[slot].gain;
        assert_eq!(out[0].angles.get(joint), Some(want), "{joint}");
    }
    assert_eq!(out[0].angles.get(Joint::ThumbIp), None);
    // A left-hand 14-sensor glove with a right-hand profile: read in full, with a warning.
    let model = glove.configure(0x5D01).unwrap();
    assert!(model.left_hand && !model.five_sensors);
    assert_eq!(glove.joints().len(), 14);
    assert!(
        glove.warnings()[0].contains("left hand"),
        "{:?}",
        glove.warnings()
    );
}

fn cyber_protocol(status_byte: bool) -> CyberGloveProtocol {
    CyberGloveProtocol {
        device: "/dev/ttyTEST".into(),
        framing: CyberGloveFraming {
            sensors: SensorCount::Eighteen,
            status_byte,
        },
        calibration: profile::resolve("cyberglove2-18")
            .unwrap()
            .glove()
            .unwrap()
            .calibration()
            .to_vec(),
    }
}

#[test]
fn a_cyberglove_out_of_its_unit_is_a_disconnect_and_a_fault() {
    let p = cyber_protocol(true);
    let mut stats = DeviceStats::default();
    let sample = |status| CyberRecord::Sample {
        header: cyberglove::STREAM,
        count: 18,
        values: [60; 22],
        status: Some(status),
    };
    let ok = p
        .convert(sample(cyberglove::STATUS_GLOVE_IN), &mut stats)
        .unwrap();
    assert!(ok.is_some());
    // The status byte without the glove-in bit.
    let e = p
        .convert(sample(cyberglove::STATUS_SWITCH), &mut stats)
        .unwrap_err();
    assert!(e.is_disconnect(), "{e}");
    assert!(e.to_string().contains("/dev/ttyTEST"), "{e}");
    // The `e g` record.
    let fault = CyberRecord::Fault {
        header: cyberglove::STREAM,
        fault: GloveFault::GloveUnplugged,
    };
    let e = p.convert(fault, &mut stats).unwrap_err();
    assert!(
        e.is_disconnect() && e.to_string().contains("unplugged"),
        "{e}"
    );
    assert_eq!(stats.faults, 2);
    // Without the status byte a sample is taken as it is.
    let p = cyber_protocol(false);
    let bare = CyberRecord::Sample {
        header: cyberglove::STREAM,
        count: 18,
        values: [60; 22],
        status: None,
    };
    assert!(p.convert(bare, &mut stats).unwrap().is_some());
}

#[test]
fn a_flagged_fastrak_record_is_dropped_and_counted() {
    let p = FastrakProtocol {
        station: 1,
        units: Units::Inches,
        framing: FastrakFraming::position_quaternion(fastrak::DataFormat::Binary),
    };
    let mut stats = DeviceStats::default();
    let record = |error| fastrak::FastrakRecord {
        station: 1,
        error,
        position: Some([1.0, 2.0, 3.0]),
        euler: None,
        quaternion: Some([1.0, 0.0, 0.0, 0.0]),
    };
    assert!(p.convert(record(b' '), &mut stats).unwrap().is_some());
    assert!(p.convert(record(b'E'), &mut stats).unwrap().is_none());
    assert!(p.convert(record(b'e'), &mut stats).unwrap().is_none());
    assert_eq!(stats.faults, 2);
}

#[test]
fn a_flock_scale_other_than_36_72_or_144_inches_is_refused() {
    let mut t = profile::resolve("flock")
        .unwrap()
        .tracker()
        .unwrap()
        .clone();
    for (scale, ok) in [(36.0, true), (72.0, true), (144.0, true), (50.0, false)] {
        if let TrackerProfile::Flock { scale_inches, .. } = &mut t {
            *scale_inches = scale;
        }
        let r = open_tracker(&t);
        assert_eq!(r.is_ok(), ok, "{scale}");
        if let Err(e) = r {
            assert!(e.to_string().contains("36, or 72 or 144"), "{e}");
        }
    }
    let json = profile::resolve("flock")
        .unwrap()
        .to_json()
        .replace("\"scale_inches\": 36.0", "\"scale_inches\": 48.0");
    assert!(json.contains("48.0"));
    let e = profile::Profile::from_json(&json, "x")
        .unwrap_err()
        .to_string();
    assert!(e.contains("scale_inches 48"), "{e}");
}
