//! What the XML loading tests share: a registry of a few leaves over a `Vec<String>`
//! context, loading with it, and a stateful action that runs for three ticks.
// Each test file uses a part of this.
#![allow(dead_code)]

use neurotree::{
    Blueprint, Handle, LoadError, PortSpec, Registry, StatefulAction, Status, XmlLoader,
};

/// The registry of these tests: a counter context and a few leaves.
pub fn registry() -> Registry<Vec<String>> {
    let mut r = Registry::<Vec<String>>::new();
    r.register_condition("Succ", vec![], |_| true).unwrap();
    r.register_condition("Fail", vec![], |_| false).unwrap();
    r.register_action(
        "Say",
        vec![PortSpec::input::<String>("message")],
        |h| match h.input::<String>("message") {
            Ok(m) => {
                h.ctx_mut().push(m);
                Status::Success
            }
            Err(e) => {
                h.ctx_mut().push(e.to_string());
                Status::Failure
            }
        },
    )
    .unwrap();
    r.register_action(
        "Produce",
        vec![
            PortSpec::input::<i64>("value").default_value("7"),
            PortSpec::output::<i64>("out"),
        ],
        |h| {
            let v: i64 = h.input("value").unwrap_or(-1);
            h.output("out", v)
                .map_or(Status::Failure, |_| Status::Success)
        },
    )
    .unwrap();
    r
}

pub fn load(text: &str) -> Result<Blueprint<Vec<String>>, LoadError> {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader.load_str(text, "test.xml")?;
    loader.build_main()
}

pub fn error(text: &str) -> LoadError {
    match load(text) {
        Err(e) => e,
        Ok(_) => panic!("expected a load error"),
    }
}

/// Runs for three ticks; records its halts in the context.
pub struct Wait3(pub u8);

impl StatefulAction<Vec<String>> for Wait3 {
    fn on_start(&mut self, _h: &mut Handle<'_, Vec<String>>) -> Status {
        self.0 = 0;
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, Vec<String>>) -> Status {
        self.0 += 1;
        if self.0 >= 3 {
            Status::Success
        } else {
            Status::Running
        }
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Vec<String>>) {
        h.ctx_mut().push("Wait3 halted".into());
    }
}
