//! The catalog of rules: code, name, severity and explanation of each, as
//! `neurotree lint --list` and `--explain` show them.

use super::Severity;

/// A lint rule as the catalog describes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rule {
    /// Its stable code, `NT0101`: the family in the second digit (1 data flow, 2
    /// reachability, 3 liveness), never reused for another rule.
    pub code: &'static str,
    /// Its name, `read-before-write`.
    pub name: &'static str,
    /// How much its findings matter.
    pub severity: Severity,
    /// One line on what it finds.
    pub summary: &'static str,
    /// Why it matters and what to do, with an example.
    pub explanation: &'static str,
}

/// Every rule, by code.
pub const RULES: &[Rule] = &[
    Rule {
        code: "NT0101",
        name: "read-before-write",
        severity: Severity::Warning,
        summary: "an input port reads an entry that nothing can have written before it is ticked",
        explanation: "\
A port bound to `{key}` reads the blackboard entry `key` when its node is ticked. If no
output port, Script, SetBlackboard, SubTree remapping or port default can have written that
entry on any path from the root before the node runs, BehaviorTree.CPP fails at that tick
(\"missing entry\").

    <Sequence>
      <SaySomething message=\"{greeting}\"/>     <!-- NT0101: nothing wrote `greeting` -->
      <Script code=\"greeting := 'hello'\"/>
    </Sequence>

Write the entry first (move the writer before the reader), remap it from the parent tree,
or, if the application sets it before the first tick, tell the linter with `--entry KEY`
(`--nav2` knows the entries Nav2's navigators write: goal, goals, ...). A write later in a
loop (Repeat, a retry, a reactive control, a RecoveryNode) reaches the read only on the next
pass: the first pass still fails, and the finding says \"on the first pass\". A write under
a node whose children run all at once (Parallel, a Switch, a control of another library)
may come first.",
    },
    Rule {
        code: "NT0102",
        name: "type-mismatch",
        severity: Severity::Error,
        summary: "an entry is written as a value that the port reading it cannot convert",
        explanation: "\
A Script or SetBlackboard writes a text into an entry, and a port whose type is a number
(or a boolean, or another typed value) reads that entry: the conversion fails at the tick
that reads it. So does a Script's number (`true` and `false` are 1 and 0) read by a port of
whole numbers that cannot take it without loss (`2.5`, `-1` for an unsigned one) or by a
port of a type of its own (a pose, a path), and a value an output port writes for a port of
another type.

    <Script code=\"count := 'three'\"/>
    <Repeat num_cycles=\"{count}\">            <!-- NT0102: 'three' is no int -->

Write a value of the port's type (`count := 3`), or read the entry with a port of text.",
    },
    Rule {
        code: "NT0103",
        name: "unused-write",
        severity: Severity::Note,
        summary: "an entry is written and never read",
        explanation: "\
An output port, Script or SetBlackboard writes an entry that no port, script or SubTree of
the tree reads. Often the entry is misspelt where it is read, or the writer is left over.
If the application reads it after the run, this note can be ignored (`--nav2` knows the
entries Nav2's navigators read: the error codes and messages, path, ...).",
    },
    Rule {
        code: "NT0201",
        name: "unreachable-child",
        severity: Severity::Warning,
        summary: "a child comes after one that always ends its parent",
        explanation: "\
A Sequence ticks its next child only when the one before succeeds (or is skipped), a
Fallback only when it fails (or is skipped). After a child that can never succeed
(AlwaysFailure, ForceFailure, an Inverter over a node that never fails) in a Sequence, or
that can never fail in a Fallback, the rest are never ticked, on any run.

    <Fallback>
      <ForceSuccess><Approach/></ForceSuccess>
      <CallForHelp/>                        <!-- NT0201: never ticked -->
    </Fallback>

Remove the child that cannot end differently, or move the others before it.",
    },
    Rule {
        code: "NT0202",
        name: "unmatched-switch-case",
        severity: Severity::Warning,
        summary: "a Switch case that no value can match",
        explanation: "\
A Switch ticks the child of the first case equal to its `variable`. A case equal to an
earlier one is never chosen, and when `variable` is a literal (not `{key}`), only the case
equal to it (or the default) can ever be.

    <Switch2 variable=\"{mode}\" case_1=\"idle\" case_2=\"idle\">   <!-- NT0202: case_2 -->

Give each case its own value, and bind `variable` to an entry.",
    },
    Rule {
        code: "NT0203",
        name: "unused-tree",
        severity: Severity::Warning,
        summary: "a tree of the file that the main tree never uses",
        explanation: "\
The file names its main tree (`main_tree_to_execute`), and another `<BehaviorTree>` of the
same file is used by no SubTree on the way from it: it never runs. Use it with a
`<SubTree ID=\"...\"/>`, or remove it.",
    },
    Rule {
        code: "NT0301",
        name: "retry-never-succeeds",
        severity: Severity::Warning,
        summary: "a loop that goes again after a failure, over a child that never succeeds",
        explanation: "\
`RetryUntilSuccessful num_attempts=\"-1\"` ticks its child again after every failure,
forever, until it succeeds (or is skipped). Over a child that can never succeed, it never
ends: it returns RUNNING on every run, once started.

    <RetryUntilSuccessful num_attempts=\"-1\">
      <AlwaysFailure/>                     <!-- NT0301 -->
    </RetryUntilSuccessful>

Give a number of attempts, or fix the child.",
    },
    Rule {
        code: "NT0302",
        name: "repeat-never-fails",
        severity: Severity::Warning,
        summary: "a loop that goes again after a success, over a child that never fails",
        explanation: "\
`Repeat num_cycles=\"-1\"` ticks its child again after every success, forever, until it
fails (or is skipped). Over a child that can never fail (the same holds for
KeepRunningUntilFailure and Nav2's RecoveryNode), it never ends; if that is meant (a main
loop), this warning says so in review.

    <Repeat num_cycles=\"-1\">
      <ForceSuccess><Patrol/></ForceSuccess>   <!-- NT0302 -->
    </Repeat>",
    },
    Rule {
        code: "NT0303",
        name: "never-finishes",
        severity: Severity::Warning,
        summary: "a tree's root can only ever return RUNNING",
        explanation: "\
A tree's root node can never return SUCCESS or FAILURE: whoever ticks it until it
finishes (`tickWhileRunning`, Nav2's navigator, a SubTree's parent) waits forever. The cause
is a loop that cannot end (see NT0301, NT0302) or a node that only runs, on every path.",
    },
];

/// The rule of `code` (`NT0101`, case-insensitive), if there is one.
pub fn rule(code: &str) -> Option<&'static Rule> {
    RULES.iter().find(|r| r.code.eq_ignore_ascii_case(code))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_and_names_are_unique_and_well_formed() {
        for (i, r) in RULES.iter().enumerate() {
            assert!(r.code.len() == 6 && r.code.starts_with("NT0"), "{}", r.code);
            for other in &RULES[i + 1..] {
                assert_ne!(r.code, other.code);
                assert_ne!(r.name, other.name);
            }
        }
        assert_eq!(rule("nt0102").map(|r| r.name), Some("type-mismatch"));
        assert!(rule("NT9999").is_none());
    }
}
