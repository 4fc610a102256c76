"""What an installed wheel must do: import the engine and tick a tree whose leaf is Python.

Run by `.ci/run` in a fresh venv where the wheel was installed with no Rust toolchain on
PATH, so that it proves the wheel needs none. It exits non-zero on any difference.
"""

from __future__ import annotations

import shutil
import sys

import neurotree as nt

XML = """
<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence>
      <Count/>
      <Count/>
      <Inverter><AlwaysSuccess/></Inverter>
    </Sequence>
  </BehaviorTree>
</root>
"""


def main() -> None:
    for tool in ("cargo", "rustc"):
        if shutil.which(tool) is not None:
            sys.exit(f"wheel check: `{tool}` is on PATH; run it where no Rust toolchain is")
    ticks: list[int] = []
    reg = nt.Registry()

    @reg.action("Count")
    def count(node: nt.Node, ctx: list[int]) -> nt.Status:
        ctx.append(len(ctx))
        return nt.SUCCESS

    tree = reg.load_string(XML, clock=nt.ManualClock())
    first = tree.tick_once(ticks)
    second = tree.tick_once(ticks)
    if (first, second, ticks) != (nt.FAILURE, nt.FAILURE, [0, 1, 2, 3]):
        sys.exit(f"wheel check: got {first}, {second}, {ticks}")
    print(f"wheel check: neurotree from {nt.__file__} ticked {len(ticks)} Python leaves")


if __name__ == "__main__":
    main()
