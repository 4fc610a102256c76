"""A robot patrols while its battery lasts, then docks: Python leaves in a BehaviorTree.CPP tree.

Run with `python crates/neurotree-py/examples/patrol.py`; `mypy --strict` checks it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import neurotree as nt

XML = """
<root BTCPP_format="4" main_tree_to_execute="Patrol">
  <BehaviorTree ID="Patrol">
    <Fallback>
      <Sequence>
        <BatteryAbove min="30"/>
        <Drive goal="{next_waypoint}" travelled="{travelled}"/>
      </Sequence>
      <Dock/>
    </Fallback>
  </BehaviorTree>
</root>
"""


@dataclass
class Robot:
    battery: float = 100.0
    position: int = 0
    log: list[str] = field(default_factory=list)


def build() -> nt.Registry:
    reg = nt.Registry()

    @reg.condition("BatteryAbove", ports={"min": float})
    def battery_above(node: nt.Node, robot: Robot) -> bool:
        return robot.battery > float(node.input("min"))

    class Drive(nt.StatefulAction):
        ports = {"goal": int, "travelled": nt.Output(int)}

        def __init__(self) -> None:
            self.steps = 0

        def on_start(self, node: nt.Node, robot: Robot) -> nt.Status:
            self.steps = 0
            robot.log.append(f"drive to {node.input('goal')}")
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Robot) -> nt.Status:
            self.steps += 1
            robot.battery -= 10.0
            node.output("travelled", self.steps)
            if robot.position + self.steps >= int(node.input("goal")):
                robot.position += self.steps
                return nt.SUCCESS
            return nt.RUNNING

        def on_halted(self, node: nt.Node, robot: Robot) -> None:
            robot.log.append("drive halted")

    reg.stateful_action("Drive", Drive)

    @reg.action("Dock")
    async def dock(node: nt.Node, robot: Robot) -> nt.Status:
        robot.log.append("docking")
        await nt.sleep(node, 0.5)
        robot.battery = 100.0
        return nt.SUCCESS

    return reg


def main() -> None:
    clock = nt.ManualClock()
    tree = build().load_string(XML, clock=clock)
    tree.blackboard["next_waypoint"] = 3
    robot = Robot(battery=55.0)
    status = tree.tick_while_running(robot, max_ticks=50, period=0.1)
    failure = tree.last_failure()
    print(status.name, robot.log, tree.blackboard["travelled"], failure)


if __name__ == "__main__":
    main()
