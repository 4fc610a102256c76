//! BehaviorTree.CPP's substitution rules: nodes replaced, when a tree is built, by a test
//! node (a `TestNodeConfig`) or by another registered node type, so that a tree can be
//! tested without the robot it drives.
//!
//! The rules read from the JSON that BehaviorTree.CPP's
//! `BehaviorTreeFactory::loadSubstitutionRuleFromJSON` reads:
//!
//! ```json
//! {
//!   "TestNodeConfigs": {
//!     "Slow": { "async_delay": 2000, "return_status": "SUCCESS", "post_script": "done := true" },
//!     "Check": { "return_status_script": "battery > 20 ? SUCCESS : FAILURE" }
//!   },
//!   "SubstitutionRules": {
//!     "MoveBase": "Slow",
//!     "nav/Check*": "Check",
//!     "Beep": "AlwaysSuccess"
//!   }
//! }
//! ```
//!
//! A rule's pattern matches a node whose name or type is the pattern, or whose path is
//! matched by it with `*` (any run of characters) and `?` (one character), as
//! BehaviorTree.CPP's `wildcards_match`. The path is BehaviorTree.CPP's: the names (else
//! IDs) of the enclosing SubTrees and the node's name (else type), joined by `/`
//! (BehaviorTree.CPP appends `::UID` to an unnamed node, which no rule can know in
//! advance). Where several rules match a node, the first that names it or its type wins,
//! then the first pattern in file order (BehaviorTree.CPP leaves the order unspecified).
//! A node a rule replaces needs no registration. A test node is a leaf: a rule naming a
//! test node leaves a node with children as it is (a control and a leaf may share a name,
//! as Nav2's RecoveryNode `ComputePathToPose` and the action it retries), while a rule
//! naming a registered type replaces any node, keeping the ports of the replaced node
//! that the new type has.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeKind, NodeStatus};
use serde::de::{Deserializer, MapAccess, Visitor};
use serde::Deserialize;

use super::{LoadError, LoadErrorKind};
use crate::script::{Enums, Script, ScriptEnv, Value};

/// How a test node behaves: BehaviorTree.CPP's `TestNodeConfig`.
#[derive(Clone, Debug, Default)]
pub struct TestNodeConfig {
    /// The status returned once complete (SUCCESS, FAILURE, RUNNING or SKIPPED; SUCCESS if
    /// not set), unless [`return_status_script`](Self::return_status_script) is set.
    pub return_status: Option<NodeStatus>,
    /// A script whose value is the status once complete; it may name SUCCESS, FAILURE,
    /// RUNNING and SKIPPED (the value is a status name or BehaviorTree.CPP's number of one).
    pub return_status_script: Option<Script>,
    /// With a delay, the node is RUNNING until this much time of the tree's clock has
    /// passed since it started, then completes.
    pub async_delay: Duration,
    /// Run when the node completes with SUCCESS.
    pub success_script: Option<Script>,
    /// Run when the node completes with FAILURE.
    pub failure_script: Option<Script>,
    /// Run whenever the node completes (after the two above).
    pub post_script: Option<Script>,
}

/// What a rule puts in the place of the nodes it matches.
#[derive(Clone, Debug)]
pub enum Substitute {
    /// A test node behaving as the config says.
    Test(Arc<TestNodeConfig>),
    /// A node of this registered type, with the ports of the replaced node that it has.
    Node(String),
}

/// A set of substitution rules, applied with [`XmlLoader::substitute`](super::XmlLoader::substitute).
#[derive(Clone, Debug, Default)]
pub struct Substitutions {
    /// Pattern and replacement, in the order given.
    rules: Vec<(String, Substitute)>,
}

impl Substitutions {
    /// No rules.
    pub fn new() -> Self {
        Self::default()
    }

    /// `true` if there is no rule.
    pub fn is_empty(&self) -> bool {
        self.rules.is_empty()
    }

    /// The rules in the order they are tried after exact matches: pattern and replacement.
    pub fn rules(&self) -> &[(String, Substitute)] {
        &self.rules
    }

    /// Adds a rule replacing the nodes `pattern` matches by `substitute`; a rule of the same
    /// pattern is replaced, as BehaviorTree.CPP's `addSubstitutionRule` does.
    pub fn add_rule(&mut self, pattern: &str, substitute: Substitute) -> &mut Self {
        match self.rules.iter_mut().find(|(p, _)| p == pattern) {
            Some(rule) => rule.1 = substitute,
            None => self.rules.push((pattern.to_string(), substitute)),
        }
        self
    }

    /// Adds every rule of `other`, after these.
    pub fn extend(&mut self, other: Substitutions) {
        for (pattern, substitute) in other.rules {
            self.add_rule(&pattern, substitute);
        }
    }

    /// The replacement for the node named `name`, of type `type_name`, at `path` (see the
    /// [module docs](self)), if a rule matches it.
    pub fn rule_for(&self, name: &str, type_name: &str, path: &str) -> Option<&Substitute> {
        let exact = self.rules.iter().find(|(p, _)| p == name || p == type_name);
        exact
            .or_else(|| self.rules.iter().find(|(p, _)| wildcards_match(path, p)))
            .map(|(_, s)| s)
    }

    /// Reads rules from BehaviorTree.CPP's JSON (see the [module docs](self)); `file` names
    /// the text in errors, which carry the line and column where the parser gives them.
    pub fn from_json(text: &str, file: &str) -> Result<Self, LoadError> {
        let json: Json = serde_json::from_str(text).map_err(|e| {
            LoadError::new(
                LoadErrorKind::Substitution,
                file,
                e.line().max(1) as u32,
                e.column().max(1) as u32,
                format!(
                    "{e}; a substitution file is an object with `SubstitutionRules` (pattern to \
                     TestNodeConfig name or node type) and optional `TestNodeConfigs`"
                ),
            )
        })?;
        let at_file =
            |message: String| LoadError::at_file(LoadErrorKind::Substitution, file, message);
        let mut configs = Vec::new();
        for (name, c) in json.configs.0 {
            if c.return_status.is_none() && c.return_status_script.is_none() {
                return Err(at_file(format!(
                    "TestNodeConfig `{name}` must contain return_status or return_status_script"
                )));
            }
            let return_status = match &c.return_status {
                Some(text) => Some(parse_status(text).ok_or_else(|| {
                    at_file(format!(
                        "TestNodeConfig `{name}`: return_status `{text}` is not SUCCESS, FAILURE, \
                         RUNNING or SKIPPED"
                    ))
                })?),
                None => None,
            };
            let script =
                |field: &str, code: &Option<String>| -> Result<Option<Script>, LoadError> {
                    code.as_deref()
                        .map(|code| {
                            Script::parse(code).map_err(|e| {
                                at_file(format!("TestNodeConfig `{name}`: {field} `{code}`: {e}"))
                            })
                        })
                        .transpose()
                };
            if c.async_delay < 0 {
                return Err(at_file(format!(
                    "TestNodeConfig `{name}`: async_delay must be milliseconds, 0 or more"
                )));
            }
            let config = TestNodeConfig {
                return_status,
                return_status_script: script("return_status_script", &c.return_status_script)?,
                async_delay: Duration::from_millis(c.async_delay as u64),
                success_script: script("success_script", &c.success_script)?,
                failure_script: script("failure_script", &c.failure_script)?,
                post_script: script("post_script", &c.post_script)?,
            };
            configs.push((name, Arc::new(config)));
        }
        let mut rules = Substitutions::new();
        for (pattern, target) in json.rules.0 {
            let substitute = match configs.iter().find(|(n, _)| *n == target) {
                Some((_, config)) => Substitute::Test(Arc::clone(config)),
                None => Substitute::Node(target),
            };
            rules.add_rule(&pattern, substitute);
        }
        Ok(rules)
    }

    /// Reads rules from a JSON file (see [`from_json`](Self::from_json)).
    pub fn read(path: impl AsRef<Path>) -> Result<Self, LoadError> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| {
            LoadError::at_file(
                LoadErrorKind::Io,
                &shown,
                format!("cannot read the substitution rules: {e}"),
            )
        })?;
        Self::from_json(&text, &shown)
    }
}

/// `true` if `pattern` matches all of `text`, `*` matching any run of characters and `?`
/// any one character, as BehaviorTree.CPP's `wildcards_match`.
pub fn wildcards_match(text: &str, pattern: &str) -> bool {
    let text: Vec<char> = text.chars().collect();
    let pattern: Vec<char> = pattern.chars().collect();
    // The last `*` seen and where in the text it was tried up to: greedy matching with
    // backtracking to the last star only, which is linear-ish and never recursive.
    let (mut t, mut p) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while t < text.len() {
        if p < pattern.len() && (pattern[p] == '?' || pattern[p] == text[t]) {
            t += 1;
            p += 1;
        } else if p < pattern.len() && pattern[p] == '*' {
            star = Some((p, t));
            p += 1;
        } else if let Some((sp, st)) = star {
            p = sp + 1;
            t = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    pattern[p..].iter().all(|&c| c == '*')
}

/// A status name as BehaviorTree.CPP's `convertFromString<NodeStatus>` reads it (IDLE is
/// refused, as a test node may not return it).
fn parse_status(text: &str) -> Option<NodeStatus> {
    Some(match text.trim() {
        "SUCCESS" => NodeStatus::Success,
        "FAILURE" => NodeStatus::Failure,
        "RUNNING" => NodeStatus::Running,
        "SKIPPED" => NodeStatus::Skipped,
        _ => return None,
    })
}

/// The JSON file's shape.
#[derive(Deserialize)]
struct Json {
    #[serde(rename = "TestNodeConfigs", default)]
    configs: Ordered<ConfigJson>,
    #[serde(rename = "SubstitutionRules")]
    rules: Ordered<String>,
}

/// A `TestNodeConfig` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ConfigJson {
    return_status: Option<String>,
    return_status_script: Option<String>,
    #[serde(default)]
    async_delay: i64,
    success_script: Option<String>,
    failure_script: Option<String>,
    post_script: Option<String>,
}

/// A JSON object's entries in file order (the rules' order decides between patterns).
struct Ordered<T>(Vec<(String, T)>);

impl<T> Default for Ordered<T> {
    fn default() -> Self {
        Ordered(Vec::new())
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Ordered<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Entries<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for Entries<T> {
            type Value = Ordered<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut entries = Vec::new();
                while let Some(entry) = map.next_entry::<String, T>()? {
                    entries.push(entry);
                }
                Ok(Ordered(entries))
            }
        }
        d.deserialize_map(Entries(std::marker::PhantomData))
    }
}

/// A test node: completes at once, or after its delay on the tree's clock, then runs its
/// scripts, as BehaviorTree.CPP's `TestNode`.
struct TestNode {
    config: Arc<TestNodeConfig>,
    enums: Arc<Enums>,
    /// The scripts' enums, with the status names `return_status_script` may use.
    status_enums: Arc<Enums>,
    /// When the node started, while it waits out its delay.
    started: Option<Duration>,
}

impl TestNode {
    /// The status once complete, after the scripts ran; `Err` for a script that failed.
    fn complete<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> Result<NodeStatus, String> {
        self.started = None;
        let (scope, stamp) = (node.scope(), node.now());
        let run = |script: &Script, enums: &Enums, node: &mut NodeCtx<'_, '_, C>| {
            let mut env = ScriptEnv::new(node.blackboard());
            env.scope = scope;
            env.enums = enums;
            env.stamp = stamp;
            script
                .eval(&mut env)
                .map_err(|e| format!("script `{}`: {e}", script.source()))
        };
        let status = match &self.config.return_status_script {
            Some(script) => match run(script, &self.status_enums, node)? {
                Value::Str(text) => parse_status(&text),
                Value::Int(n) => match n {
                    1 => Some(NodeStatus::Running),
                    2 => Some(NodeStatus::Success),
                    3 => Some(NodeStatus::Failure),
                    4 => Some(NodeStatus::Skipped),
                    _ => None,
                },
                _ => None,
            }
            .ok_or_else(|| {
                format!(
                    "return_status_script `{}` did not give SUCCESS, FAILURE, RUNNING or SKIPPED",
                    script.source()
                )
            })?,
            None => self.config.return_status.unwrap_or(NodeStatus::Success),
        };
        let then = match status {
            NodeStatus::Success => self.config.success_script.as_ref(),
            NodeStatus::Failure => self.config.failure_script.as_ref(),
            _ => None,
        };
        for script in then.into_iter().chain(self.config.post_script.as_ref()) {
            run(script, &self.enums, node)?;
        }
        Ok(status)
    }
}

impl<C> CustomNode<C> for TestNode {
    // When its delay began, as the tree's clock read: what a resumed run must go on from.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.started))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|started| self.started = started)
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let now = node.now();
        let due = match self.started {
            _ if self.config.async_delay.is_zero() => true,
            Some(started) => now.saturating_sub(started) >= self.config.async_delay,
            None => {
                self.started = Some(now);
                false
            }
        };
        if !due {
            return NodeStatus::Running;
        }
        match self.complete(node) {
            Ok(status) => status,
            Err(e) => {
                node.fail(format!("test node: {e}"));
                NodeStatus::Failure
            }
        }
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.started = None;
    }
}

/// A leaf kind behaving as `config` says (a fresh state per tree instance).
pub(crate) fn test_kind<C>(config: &Arc<TestNodeConfig>, enums: &Arc<Enums>) -> NodeKind<C> {
    let config = Arc::clone(config);
    let enums = Arc::clone(enums);
    let mut with_status = (*enums).clone();
    for (name, status) in [
        ("IDLE", 0),
        ("RUNNING", 1),
        ("SUCCESS", 2),
        ("FAILURE", 3),
        ("SKIPPED", 4),
    ] {
        with_status.insert(name, status);
    }
    let status_enums = Arc::new(with_status);
    NodeKind::Custom(Box::new(CustomSpec::new(
        "TestNode",
        Arity::Leaf,
        Box::new(move || {
            Box::new(TestNode {
                config: Arc::clone(&config),
                enums: Arc::clone(&enums),
                status_enums: Arc::clone(&status_enums),
                started: None,
            })
        }),
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wildcards_match_as_behaviortree_cpp() {
        assert!(wildcards_match("nav/action_1", "nav/action_*"));
        assert!(wildcards_match("abc", "a?c"));
        assert!(wildcards_match("", "*"));
        assert!(wildcards_match("a/b/c", "*c"));
        assert!(wildcards_match("aXbYb", "a*b"));
        assert!(!wildcards_match("abc", "a?"));
        assert!(!wildcards_match("abd", "*c"));
        assert!(!wildcards_match("ab", "abc*d"));
    }

    #[test]
    fn exact_names_win_over_patterns() {
        let rules = Substitutions::from_json(
            r#"{"SubstitutionRules": {"*": "AlwaysFailure", "Beep": "AlwaysSuccess"}}"#,
            "r.json",
        )
        .unwrap();
        let pick = |name, ty, path| match rules.rule_for(name, ty, path) {
            Some(Substitute::Node(n)) => n.clone(),
            other => panic!("{other:?}"),
        };
        assert_eq!(pick("b", "Beep", "b"), "AlwaysSuccess");
        assert_eq!(pick("x", "Other", "x"), "AlwaysFailure");
    }
}
