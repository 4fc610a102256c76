//! What the build script makes of the definitions under `interfaces/`: the reader's
//! answers to good and bad files, and the generated types' defaults, constants, traits and
//! names.

// The build script's reader and writer, compiled again here to be tested; the build script
// uses all of them.
#[allow(dead_code)]
#[path = "../../build/idl.rs"]
mod idl;
#[allow(dead_code)]
#[path = "../../build/rust.rs"]
mod rust;

use std::path::Path;

use idl::{parse, Array, Kind};
use rust::{generate, Definitions, Origin};

use super::geometry_msgs::Quaternion;
use super::nav2_msgs::{self, kilted, main, DockRobotGoal, DockRobotResult, SpinResult};
use super::sensor_msgs::BatteryState;
use crate::{RosAction, RosMessage, RosService};

fn error(kind: Kind, text: &str) -> String {
    parse(Path::new("pkg/msg/Bad.msg"), kind, text)
        .unwrap_err()
        .to_string()
}

#[test]
fn a_definition_reads_as_its_doc_constants_and_fields_in_order() {
    let text = "# A thing.\n\n# No error.\nuint16 NONE=0\n\nfloat64[36] covariance\n\
                string<=8 name  # Its name.\nHeader[] headers\nbool on true\n";
    let thing = parse(Path::new("p/msg/Thing.msg"), Kind::Message, text).unwrap();
    assert_eq!(thing.name, "Thing");
    assert_eq!(thing.doc, ["A thing."]);
    let part = &thing.parts[0];
    assert_eq!(part.constants.len(), 1);
    assert_eq!(
        (part.constants[0].value.as_str(), &part.constants[0].doc[..]),
        ("0", &["No error.".to_owned()][..])
    );
    let fields: Vec<(&str, &str, Array)> = part
        .fields
        .iter()
        .map(|f| (f.name.as_str(), f.ty.base.as_str(), f.ty.array))
        .collect();
    assert_eq!(
        fields,
        [
            ("covariance", "float64", Array::Fixed(36)),
            ("name", "string", Array::None),
            ("headers", "Header", Array::Counted),
            ("on", "bool", Array::None),
        ]
    );
    assert_eq!(part.fields[1].doc, ["Its name."]);
    assert_eq!(part.fields[3].default.as_deref(), Some("true"));
}

#[test]
fn an_action_has_three_parts_and_a_service_two() {
    let spin = "float32 yaw\n---\nuint16 code\n---\nfloat32 turned\n";
    let action = parse(Path::new("p/action/Spin.action"), Kind::Action, spin).unwrap();
    assert_eq!(action.parts.len(), 3);
    assert_eq!(action.parts[2].fields[0].name, "turned");
    assert_eq!(
        error(Kind::Service, "bool a\n"),
        "pkg/msg/Bad.msg: error: a .srv file has 2 parts separated by `---`; this one has 1"
    );
    assert_eq!(
        error(Kind::Service, "bool a\n---\n---\n"),
        "pkg/msg/Bad.msg:3:1: error: a .srv file has 2 parts: one `---` too many"
    );
}

#[test]
fn a_bad_line_names_its_file_and_line_and_what_to_write() {
    assert_eq!(
        error(Kind::Message, "# ok\nfloat64\n"),
        "pkg/msg/Bad.msg:2:1: error: `float64` is not `TYPE NAME`: a field needs a name"
    );
    assert_eq!(
        error(Kind::Message, "wstring name\n"),
        "pkg/msg/Bad.msg:1:1: error: `wstring` is not read here: use `string` (UTF-8)"
    );
    assert_eq!(
        error(Kind::Message, "float64<=3 v\n"),
        "pkg/msg/Bad.msg:1:1: error: `float64<=3`: only strings take a `<=` bound"
    );
    assert_eq!(
        error(Kind::Message, "geometry_msgs/Pose-2 p\n"),
        "pkg/msg/Bad.msg:1:1: error: `geometry_msgs/Pose-2` is neither a primitive type nor `package/Message`"
    );
    assert_eq!(
        error(Kind::Message, "float64[x] v\n"),
        "pkg/msg/Bad.msg:1:1: error: `float64[x]`: the length of an array is a number"
    );
    assert_eq!(
        error(Kind::Message, "int32 Speed\n"),
        "pkg/msg/Bad.msg:1:1: error: `Speed` is not a field name: use lower case, digits and `_`"
    );
    assert_eq!(
        error(Kind::Message, "geometry_msgs/Pose ORIGIN=0\n"),
        "pkg/msg/Bad.msg:1:1: error: the constant `ORIGIN` has type `geometry_msgs/Pose`: constants are of a primitive type"
    );
    assert_eq!(
        error(Kind::Message, "int32[] v 1\n"),
        "pkg/msg/Bad.msg:1:1: error: `v` gives an array a default value: only single values have defaults here"
    );
    let lower = parse(Path::new("p/msg/thing.msg"), Kind::Message, "");
    assert_eq!(
        lower.unwrap_err().to_string(),
        "p/msg/thing.msg: error: `thing` is not a type name: name the file in CamelCase"
    );
}

#[test]
fn generated_types_take_the_definitions_defaults_and_constants() {
    assert_eq!(Quaternion::default().w, 1.0);
    assert_eq!(Quaternion::default().z, 0.0);
    let dock = DockRobotGoal::default();
    assert!(dock.use_dock_id && dock.navigate_to_staging_pose);
    assert_eq!(dock.max_staging_time, 1000.0);
    assert!(DockRobotResult::default().success);
    assert_eq!(DockRobotResult::FAILED_TO_CHARGE, 906);
    assert_eq!(BatteryState::POWER_SUPPLY_STATUS_FULL, 4);
    assert_eq!(nav2_msgs::NavigateToPoseResult::UNKNOWN, 9000);
}

#[test]
fn generated_types_carry_their_ros_2_names() {
    assert_eq!(BatteryState::TYPE, ("sensor_msgs", "BatteryState"));
    assert_eq!(nav2_msgs::Route::TYPE, ("nav2_msgs", "Route"));
    assert_eq!(<nav2_msgs::Spin as RosAction>::TYPE, ("nav2_msgs", "Spin"));
    assert_eq!(<kilted::Spin as RosAction>::TYPE, ("nav2_msgs", "Spin"));
    assert_eq!(
        <main::ClearEntireCostmap as RosService>::TYPE,
        ("nav2_msgs", "ClearEntireCostmap")
    );
}

#[test]
fn a_releases_part_laid_out_as_the_bases_is_the_bases_type() {
    // Compiles only if Kilted's Spin answers with Jazzy's result type.
    let jazzy: fn(<kilted::Spin as RosAction>::Result) -> SpinResult = |r| r;
    assert_eq!(jazzy(SpinResult::default()), SpinResult::default());
    let feedback: fn(<main::FollowPath as RosAction>::Result) -> nav2_msgs::FollowPathResult =
        |r| r;
    assert_eq!(feedback(Default::default()).error_code, 0);
}

/// The definitions of `files` (package, release, path, text), as the build script reads them.
fn definitions(files: &[(&str, Option<&str>, &str, &str)]) -> Definitions {
    let mut all = Definitions::new();
    for (package, release, path, text) in files {
        let kind = match path.rsplit('.').next() {
            Some("msg") => Kind::Message,
            Some("srv") => Kind::Service,
            _ => Kind::Action,
        };
        let origin = Origin {
            package: (*package).to_owned(),
            release: release.map(str::to_owned),
        };
        let interface = parse(Path::new(path), kind, text).unwrap();
        all.entry(origin).or_default().push(interface);
    }
    all
}

fn origin(package: &str, release: Option<&str>) -> Origin {
    Origin {
        package: package.to_owned(),
        release: release.map(str::to_owned),
    }
}

#[test]
fn the_writer_derives_what_the_fields_allow_and_names_the_ros_2_type() {
    let all = definitions(&[
        ("p", None, "p/msg/Stamp.msg", "int32 sec\n"),
        (
            "p",
            None,
            "p/msg/Reading.msg",
            "# A reading.\n\nStamp stamp\nfloat32 value 1.5\n",
        ),
        ("p", None, "p/msg/Names.msg", "string[] names\n"),
    ]);
    let code = generate(&all, &origin("p", None)).unwrap();
    assert!(code.contains("#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ::serde::Serialize, ::serde::Deserialize)]\npub struct Stamp {"), "{code}");
    // A default value: `Default` is written, not derived; a float: no `Eq`.
    assert!(code.contains("#[derive(Clone, Copy, Debug, PartialEq, ::serde::Serialize, ::serde::Deserialize)]\npub struct Reading {"), "{code}");
    assert!(code.contains("            value: 1.5_f32,"), "{code}");
    assert!(
        code.contains("    pub stamp: crate::msg::p::Stamp,"),
        "{code}"
    );
    assert!(
        code.contains("    pub names: ::std::vec::Vec<::std::string::String>,"),
        "{code}"
    );
    assert!(
        code.contains("const TYPE: (&'static str, &'static str) = (\"p\", \"Reading\");"),
        "{code}"
    );
}

#[test]
fn the_writer_shares_a_releases_unchanged_parts_and_refuses_an_unknown_message() {
    let all = definitions(&[
        (
            "p",
            None,
            "p/action/Go.action",
            "float32 x\n---\nuint16 NONE=0\nuint16 code\n---\n",
        ),
        (
            "p",
            Some("next"),
            "p/next/action/Go.action",
            "float32 x\nbool fast\n---\nuint16 NONE=0\nuint16 code\n---\n",
        ),
        ("q", None, "q/msg/Bad.msg", "p/Missing thing\n"),
    ]);
    let code = generate(&all, &origin("p", Some("next"))).unwrap();
    assert!(code.contains("pub struct GoGoal {"), "{code}");
    assert!(
        code.contains("    type Result = crate::msg::p::GoResult;"),
        "{code}"
    );
    assert!(
        code.contains("    type Feedback = crate::msg::p::GoFeedback;"),
        "{code}"
    );
    assert!(!code.contains("pub struct GoResult"), "{code}");
    let base = generate(&all, &origin("p", None)).unwrap();
    // An empty part has the byte ROS 2 gives it.
    assert!(
        base.contains("pub struct GoFeedback {\n    /// Always 0"),
        "{base}"
    );
    assert_eq!(
        generate(&all, &origin("q", None)).unwrap_err(),
        "q/msg/Bad.msg: error: no definition of the message `p/Missing`: add its .msg file under interfaces/"
    );
}
