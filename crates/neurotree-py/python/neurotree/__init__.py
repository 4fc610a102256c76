"""NeuroTree from Python: behavior trees with BehaviorTree.CPP's semantics and XML, ticked by
NeuroTree's Rust engine, with leaves written in Python.

    import neurotree as nt

    reg = nt.Registry()

    @reg.condition("BatteryOK", ports={"min": int})
    def battery_ok(node, robot):
        return robot["battery"] >= node.input("min")

    tree = reg.load_string(XML, clock=nt.ManualClock())
    status = tree.tick_once(robot)

The engine is the extension module ``neurotree._native``; this module adds what is most
natural in Python: the ``Status`` enum, the exceptions, the port declarations, the
decorators that register leaves, and the awaitables ``async def`` leaves use.
"""

from __future__ import annotations

import contextlib
import enum
import inspect
import json
import pickle
from typing import Any, Callable, Dict, Generator, Iterator, List, Mapping, Optional, Tuple, TypeVar, Union

from . import _native, studio
from ._native import Blackboard, Coverage, Failure, ManualClock, Node, SystemClock, Tree
from .campaigns import Campaign
from .scenarios import ScenarioResult, ScenarioResults, run_scenarios

__all__ = [
    "Status",
    "SUCCESS",
    "FAILURE",
    "RUNNING",
    "NeuroTreeError",
    "LoadError",
    "NodeError",
    "TreeBusy",
    "Registry",
    "Builder",
    "Tree",
    "Node",
    "Blackboard",
    "Failure",
    "Coverage",
    "ManualClock",
    "SystemClock",
    "StatefulAction",
    "Input",
    "Output",
    "InOut",
    "next_tick",
    "sleep",
    "studio",
    "run_scenarios",
    "Campaign",
    "ScenarioResult",
    "ScenarioResults",
]


class Status(enum.IntEnum):
    """A node's status, numbered as BehaviorTree.CPP numbers them.

    Leaves return ``SUCCESS``, ``FAILURE`` or ``RUNNING``; observers also see ``IDLE`` (not
    ticked since the last reset) and ``SKIPPED`` (a precondition skipped the node).
    """

    IDLE = 0
    RUNNING = 1
    SUCCESS = 2
    FAILURE = 3
    SKIPPED = 4

    # Read as their names (`SUCCESS`), as printed statuses are, rather than as the
    # numbers an IntEnum shows.
    def __str__(self) -> str:
        return self.name

    def __repr__(self) -> str:
        return self.name


SUCCESS = Status.SUCCESS
FAILURE = Status.FAILURE
RUNNING = Status.RUNNING


class NeuroTreeError(Exception):
    """The base of NeuroTree's errors."""


class LoadError(NeuroTreeError):
    """A tree file or text that does not load: the message is what ``neurotree check``
    prints (``file:line:col: error: ...``) for the first error; ``errors`` has them all."""

    def __init__(
        self,
        message: str,
        kind: str,
        file: str,
        line: int,
        column: int,
        errors: "Optional[List[LoadError]]" = None,
    ) -> None:
        super().__init__(message)
        #: The ``LoadErrorKind`` name (``"UnknownNode"``, ``"Syntax"``, ...).
        self.kind = kind
        #: The file, as given (``"<string>"`` for text).
        self.file = file
        #: The 1-based line.
        self.line = line
        #: The 1-based column.
        self.column = column
        #: Every error of the tree, in document order, this one first (a tree with several
        #: mistakes lists them all, as ``neurotree check`` does).
        self.errors: List[LoadError] = errors if errors is not None else [self]


class NodeError(NeuroTreeError):
    """A tick that a node ended: a leaf raised (its exception is ``__cause__``), returned
    something that is no status, or read or wrote a port wrongly. The tree was halted and
    the next tick starts afresh."""

    def __init__(self, message: str, path: Optional[str] = None) -> None:
        super().__init__(message)
        #: The path of the node (``"Sequence/MoveTo"``), or ``None``.
        self.path = path


class TreeBusy(NeuroTreeError, RuntimeError):
    """A tree was ticked, halted, reloaded or read while a call ticks it, from another thread
    or from a leaf of that very tick. Raised at once rather than waiting for the tick to end:
    a leaf that waits for a thread using its own tree would wait for ever. A leaf reaches its
    tree's blackboard through its node (``node.get``, ``node.set``); another thread tries
    again once the tick is done."""


_native._bind(Status, LoadError, NodeError)
_native._bind_busy(TreeBusy)

PortType = Union[type, None]


class _Port:
    direction = "input"

    def __init__(self, type: PortType = None, default: Any = None, description: str = "") -> None:
        self.type = type
        self.default = default
        self.description = description


class Input(_Port):
    """An input port: ``ports={"speed": nt.Input(float, default=0.5)}``. A bare type
    (``{"speed": float}``) is an input too."""

    direction = "input"


class Output(_Port):
    """An output port: ``ports={"steps": nt.Output(int)}``."""

    direction = "output"


class InOut(_Port):
    """A port read and written."""

    direction = "inout"


_TYPE_NAMES = {int: "int", float: "float", bool: "bool", str: "str", list: "list", dict: "dict"}

PortDecl = Tuple[str, str, str, Optional[str], str]


def _port_tuples(ports: Optional[Mapping[str, Any]]) -> list[PortDecl]:
    out: list[PortDecl] = []
    for name, spec in (ports or {}).items():
        port = spec if isinstance(spec, _Port) else Input(spec)
        if port.type is None or port.type is object:
            type_name = "any"
        elif port.type in _TYPE_NAMES:
            type_name = _TYPE_NAMES[port.type]
        else:
            raise TypeError(
                f"port {name!r}: a port is int, float, bool, str, list, dict or object, not {port.type!r}"
            )
        default: Optional[str] = None
        if port.default is not None:
            if isinstance(port.default, bool):
                default = "true" if port.default else "false"
            elif isinstance(port.default, (list, dict)):
                default = "json:" + json.dumps(port.default)
            else:
                default = str(port.default)
        out.append((name, port.direction, type_name, default, port.description))
    return out


F = TypeVar("F", bound=Callable[..., Any])


class StatefulAction:
    """An action that runs over several ticks; subclass it and register the class with
    ``Registry.stateful_action``. Each tree makes one instance per node.

    ``on_start`` is called on the tick that starts it, ``on_running`` on the ticks after
    while it returns ``RUNNING``, ``on_halted`` once if it is halted while Running. Ports
    are declared by the class attribute ``ports``.
    """

    ports: Dict[str, Any] = {}

    def on_start(self, node: Node, robot: Any) -> Status:
        """Called on the tick that starts the action; ``RUNNING`` to go on next tick."""
        return Status.RUNNING

    def on_running(self, node: Node, robot: Any) -> Status:
        """Called on each later tick while the action is Running."""
        return Status.SUCCESS

    def on_halted(self, node: Node, robot: Any) -> None:
        """Called once when the action is halted while Running: stop what it started."""

    def save_state(self) -> bytes:
        """The instance's state, for ``Tree.save_state()``: by default its attributes,
        pickled. Override with ``restore_state`` for state that does not pickle."""
        return pickle.dumps(self.__dict__)

    def restore_state(self, state: bytes) -> None:
        """Takes back what ``save_state`` gave, into a fresh instance."""
        self.__dict__.update(pickle.loads(state))


class Registry(_native.Registry):
    """Node types by name: every built-in node of BehaviorTree.CPP, and the leaves you add."""

    def condition(self, name: str, ports: Optional[Mapping[str, Any]] = None) -> Callable[[F], F]:
        """Registers the decorated ``f(node, robot) -> bool`` as condition ``name``."""

        def register(func: F) -> F:
            self.register_condition(name, func, _port_tuples(ports))
            return func

        return register

    def action(self, name: str, ports: Optional[Mapping[str, Any]] = None) -> Callable[[F], F]:
        """Registers the decorated ``f(node, robot) -> Status`` as action ``name``; an
        ``async def`` runs over as many ticks as it awaits (see ``next_tick``)."""

        def register(func: F) -> F:
            if inspect.iscoroutinefunction(func):
                self.register_async_action(name, func, _port_tuples(ports))
            else:
                self.register_action(name, func, _port_tuples(ports))
            return func

        return register

    def stateful_action(self, name: str, cls: "type[StatefulAction]") -> None:
        """Registers ``cls``, a ``StatefulAction`` subclass, as action ``name``."""
        self.register_stateful_action(name, cls, _port_tuples(getattr(cls, "ports", None)))


class Builder(_native.Builder):
    """A tree built in code: the built-in nodes by their BehaviorTree.CPP names, and Python
    leaves given as functions and classes.

        b = nt.Builder()
        with b.node("Sequence", name="patrol"):
            b.condition("battery_ok", lambda node, robot: robot["battery"] > 20)
            with b.node("Repeat", num_cycles=2):
                b.action("say", say)
        tree = b.build(clock=nt.ManualClock())

    Keyword arguments bind ports: ``"{key}"`` is a blackboard entry, anything else a literal.
    """

    @contextlib.contextmanager
    def node(self, type_name: str, name: Optional[str] = None, **ports: Any) -> Iterator["Builder"]:
        """Opens the built-in control or decorator ``type_name``; the nodes added in the
        ``with`` block are its children."""
        self.open(type_name, name, **ports)
        yield self
        self.close()

    def condition(
        self, name: str, func: Callable[[Node, Any], Any], ports: Optional[Mapping[str, Any]] = None, **bind: Any
    ) -> "Builder":
        """Adds condition ``name``: ``func(node, robot) -> bool``."""
        self.add_condition(name, func, _port_tuples(ports), bind)
        return self

    def action(
        self, name: str, func: Callable[[Node, Any], Any], ports: Optional[Mapping[str, Any]] = None, **bind: Any
    ) -> "Builder":
        """Adds action ``name``: ``func(node, robot) -> Status``, or an ``async def``."""
        if inspect.iscoroutinefunction(func):
            self.add_async_action(name, func, _port_tuples(ports), bind)
        else:
            self.add_action(name, func, _port_tuples(ports), bind)
        return self

    def stateful_action(self, name: str, cls: "type[StatefulAction]", **bind: Any) -> "Builder":
        """Adds action ``name``: an instance of ``cls`` (a ``StatefulAction`` subclass) per tree."""
        self.add_stateful_action(name, cls, _port_tuples(getattr(cls, "ports", None)), bind)
        return self


class _NextTick:
    def __await__(self) -> Generator[None, None, None]:
        yield None


def next_tick() -> _NextTick:
    """In an ``async def`` leaf: ``await nt.next_tick()`` returns ``RUNNING`` for this tick
    and goes on at the next."""
    return _NextTick()


async def sleep(node: Node, seconds: float) -> None:
    """In an ``async def`` leaf: waits ``seconds`` on the tree's clock, one tick at a time."""
    until = node.now + seconds
    while node.now < until:
        await next_tick()
