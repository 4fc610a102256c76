// The editor's problems: the server's check of the file (errors, warnings, lint notes)
// listed under the drawing, each that names a node a click away from it, and put on the
// drawn nodes as `data-error` / `data-warning`. Apart from editor.js because the check's
// answer is kept (`state.check`) and shown here alone: what the user does about a problem
// is the editor's actions.

/** Shows `check` (the server's answer for the file) in the problem list and on the nodes. */
export function showCheck(view, check) {
  const { state, $, section, actions } = view;
  state.check = check;
  const list = $(".problem-list");
  list.innerHTML = "";
  const problems = [];
  if (state.file?.error) problems.push({ severity: "error", message: `not well-formed XML: ${state.file.error}`, tree: null, element: null });
  if (state.file?.repaired) {
    problems.push({ severity: "warning", message: "this file has a bare & or < inside an attribute, which XML forbids (BehaviorTree.CPP reads it); the editor saves it escaped (&amp; &lt;), which loads the same", tree: null, element: null });
  }
  for (const e of check?.errors || []) problems.push({ severity: "error", ...e });
  for (const w of check?.warnings || []) problems.push({ severity: "warning", ...w });
  for (const l of check?.lint || []) problems.push(l);
  for (const p of problems.slice(0, 200)) {
    const li = document.createElement("li");
    li.dataset.severity = p.severity;
    li.textContent = p.message;
    if (p.tree && p.element) {
      li.classList.add("located");
      li.addEventListener("click", () => {
        if (p.tree !== state.treeId) actions.openTab(p.tree);
        actions.select(p.element, true);
      });
    }
    list.append(li);
  }
  if (problems.length > 200) {
    const li = document.createElement("li");
    li.textContent = `… and ${problems.length - 200} more`;
    list.append(li);
  }
  const count = (severity, one, many) => {
    const n = problems.filter((p) => p.severity === severity).length;
    return `${n} ${n === 1 ? one : many}`;
  };
  const errors = problems.filter((p) => p.severity === "error").length;
  const notes = problems.some((p) => p.severity === "note") ? `, ${count("note", "note", "notes")}` : "";
  $(".problem-count").textContent = problems.length
    ? `(${count("error", "error", "errors")}, ${count("warning", "warning", "warnings")}${notes})`
    : "none";
  section.dataset.check = errors ? "errors" : "ok";
  markProblems(view);
}

/** Puts the last check's problems on the nodes of the tree shown, and in the side panel. */
export function markProblems(view) {
  const { state, drawing, indexOfElement, renderPanel } = view;
  drawing.clearMarks("data-error");
  drawing.clearMarks("data-warning");
  const check = state.check;
  if (!check) return;
  const put = (items, attr) => {
    for (const p of items || []) {
      if (p.tree !== state.treeId || !p.element) continue;
      const i = indexOfElement(p.element);
      if (i >= 0) drawing.mark(i, attr, p.message);
    }
  };
  put(check.warnings, "data-warning");
  put((check.lint || []).filter((p) => p.severity !== "error"), "data-warning");
  put(check.errors, "data-error");
  put((check.lint || []).filter((p) => p.severity === "error"), "data-error");
  renderPanel();
}
