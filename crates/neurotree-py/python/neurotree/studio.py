"""The browser studio, watching a tree that Python ticks.

    url = nt.studio.watch(tree)      # http://127.0.0.1:PORT/
    while tree.tick_once(robot) is nt.RUNNING: ...

The page shows the tree's statuses as it runs, its blackboard and why it failed; pausing,
stepping and blackboard edits in the page take effect between ticks, with Python leaves as
with any other.
"""

from __future__ import annotations

from ._native import Tree

__all__ = ["watch"]


def watch(tree: Tree, port: int = 0, name: str = "tree") -> str:
    """Serves the studio on 127.0.0.1:``port`` (0 picks a free one), shows ``tree`` in it as
    ``name`` and returns the page's URL. The server stops when the tree is dropped."""
    return tree._watch_in_studio(port, name)
