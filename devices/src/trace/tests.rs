use super::*;

#[test]
fn frame_errors_are_typed_and_keep_their_messages() {
    let joints = [Joint::IndexMcp];
    let cases: [(&str, FrameError, &str); 8] = [
        ("", FrameError::Empty, "empty line"),
        ("0 ok", FrameError::EndsEarly, "the line ends early"),
        (
            "x ok ok 0 P - J -",
            FrameError::BadTime,
            "the time is not a whole number of microseconds",
        ),
        (
            "0 up ok 0 P - J -",
            FrameError::UnknownState("up".into()),
            "unknown source state `up`",
        ),
        (
            "0 ok ok 0 P 1.5 J -",
            FrameError::NotSixDecimals("1.5".into()),
            "`1.5` is not a number with 6 decimals",
        ),
        (
            "0 lost ok 0 P 0.000000 J -",
            FrameError::PoseWithoutTracker(SourceState::Disconnected),
            "the tracker is `lost` but the frame has a pose: only an `ok` source carries values",
        ),
        (
            "0 ok silent 0 P - J 0.100000",
            FrameError::AnglesWithoutGlove(SourceState::Silent),
            "the glove is `silent` but the frame has joint angles: only an `ok` source carries values",
        ),
        (
            "0 ok ok 0 P - J 0.100000 0.200000",
            FrameError::JointCount {
                found: 2,
                expected: 1,
            },
            "2 joint columns, the header names 1",
        ),
    ];
    for (line, want, message) in cases {
        let e = parse_frame(&joints, line).unwrap_err();
        assert_eq!(e, want, "{line}");
        assert_eq!(e.to_string(), message, "{line}");
    }
    assert!(matches!(
        parse_frame(&joints, "0 ok ok 0 P - J 9.000000"),
        Err(FrameError::BadJoint(_))
    ));
    assert!(matches!(
        parse_frame(
            &joints,
            "0 ok ok 0 P 0.000000 0.000000 0.000000 0.000000 0.000000 0.000000 0.000000 J -"
        ),
        Err(FrameError::BadPose(_))
    ));
}
