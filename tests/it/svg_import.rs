//! SVG import through a real XML parser: a `>` inside an attribute, transforms on the path and
//! on its ancestors, entities, both quotes, and malformed XML refused with a clear error.

use glam::DVec2;
use nendo::curve::svg::{SvgError, read_svg};

fn close(a: DVec2, b: DVec2) -> bool {
    (a - b).length() < 1e-12
}

#[test]
fn a_greater_than_inside_an_attribute_does_not_end_the_tag() {
    let doc = r#"<svg xmlns="http://www.w3.org/2000/svg"><path data-note="a > b" d="M 0 0 L 1 1"/></svg>"#;
    let paths = read_svg(doc).expect("valid");
    assert_eq!(paths.len(), 1);
    assert_eq!(paths[0].segments[0].points(), &[DVec2::ZERO, DVec2::ONE]);
    // A `d` that appears only inside another attribute's value is not the path's data.
    let doc = r#"<svg><path title='d="M 5 5 L 6 6"' d="M 0 0 L 2 0"/></svg>"#;
    let paths = read_svg(doc).expect("valid");
    assert_eq!(paths[0].segments[0].points()[1], DVec2::new(2.0, 0.0));
}

#[test]
fn transforms_of_the_path_and_its_groups_are_applied() {
    let doc = r#"<svg xmlns="http://www.w3.org/2000/svg">
      <g transform="translate(10 20)">
        <g transform="scale(2)">
          <path transform="rotate(90)" d="M 1 0 L 2 0"/>
        </g>
        <path d="M 0 0 L 1 0" transform="matrix(1 0 0 1 5 5) skewX(45)"/>
      </g>
      <path d="M 1 1 L 2 2"/>
    </svg>"#;
    let paths = read_svg(doc).expect("valid");
    assert_eq!(paths.len(), 3);
    // rotate(90): (1,0) → (0,1); scale(2) → (0,2); translate → (10,22).
    let p = paths[0].segments[0].points();
    assert!(close(p[0], DVec2::new(10.0, 22.0)), "{p:?}");
    assert!(close(p[1], DVec2::new(10.0, 24.0)), "{p:?}");
    // skewX(45) leaves y = 0 points in place; then +5 and the group's translation.
    let p = paths[1].segments[0].points();
    assert!(close(p[0], DVec2::new(15.0, 25.0)), "{p:?}");
    assert!(close(p[1], DVec2::new(16.0, 25.0)), "{p:?}");
    // Outside the groups: untouched, bit for bit.
    assert_eq!(
        paths[2].segments[0].points(),
        &[DVec2::ONE, DVec2::splat(2.0)]
    );
    // A rotation about a centre: rotate(180 1 1) maps (0,0) to (2,2).
    let doc = r#"<svg><path transform="rotate(180, 1, 1)" d="M 0 0 Q 1 0 1 1"/></svg>"#;
    let p = read_svg(doc).expect("valid")[0].segments[0]
        .points()
        .to_vec();
    assert!(
        close(p[0], DVec2::splat(2.0)) && close(p[1], DVec2::new(1.0, 2.0)),
        "{p:?}"
    );
}

#[test]
fn entities_and_both_quotes_are_read() {
    let doc = "<!DOCTYPE svg [<!ENTITY start \"M 3 4\">]>\
        <svg><path d='&start; L&#32;5&#x20;6'/><path d=\"M 0 0 L 1 &#49;\" id='it&apos;s &gt; &amp;'/></svg>";
    let paths = read_svg(doc).expect("valid");
    assert_eq!(paths.len(), 2);
    assert_eq!(
        paths[0].segments[0].points(),
        &[DVec2::new(3.0, 4.0), DVec2::new(5.0, 6.0)]
    );
    assert_eq!(paths[1].segments[0].points()[1], DVec2::ONE);
    // CDATA and comments hold no paths.
    let doc = "<svg><!-- <path d='M 9 9 L 0 0'/> --><style><![CDATA[ <path d='M 1 1 L 2 2'/> ]]></style></svg>";
    assert_eq!(read_svg(doc).expect("valid"), vec![]);
}

#[test]
fn malformed_documents_and_data_are_refused_clearly() {
    for bad in [
        "<svg><path d='M 0 0 L 1 1'></svg>",
        "<svg><path d='M 0 0 L 1 1/></svg>",
        "<svg><path d=\"M 0 0\" d=\"M 1 1\"/></svg>",
        "<svg><path d='&undefined;'/></svg>",
        "",
    ] {
        let e = read_svg(bad).expect_err(bad);
        assert!(matches!(e, SvgError::Xml(_)), "{bad}: {e:?}");
        assert!(
            e.to_string()
                .starts_with("the document is not well-formed XML"),
            "{e}"
        );
    }
    let e = read_svg("<svg><g transform='spin(3)'><path d='M 0 0 L 1 1'/></g></svg>")
        .expect_err("bad transform");
    assert!(
        matches!(&e, SvgError::Transform { index: 0, element, .. } if element == "g"),
        "{e:?}"
    );
    let e =
        read_svg("<svg><path d='M 0 0 L 1 1'/><path d='M 0 0 L 1'/></svg>").expect_err("bad data");
    assert!(matches!(&e, SvgError::InPath { index: 1, .. }), "{e:?}");
    assert!(e.to_string().starts_with("path 1: "), "{e}");
    let e = read_svg("<svg><path d='M 0 0 A 1 1 0 0 1 2 2'/></svg>").expect_err("arc");
    assert_eq!(
        e.to_string(),
        "path 0: elliptical arc commands (A) are not supported"
    );
    let e = read_svg("<svg><path transform='scale(1e300)' d='M 0 0 L 1e300 0'/></svg>")
        .expect_err("overflow");
    assert!(e.to_string().contains("not a finite number"), "{e}");
}
