"""The engine: NeuroTree's Rust extension module. Use it through ``neurotree``."""

from os import PathLike
from typing import Any, Callable, List, Optional, Sequence, Tuple, Union

from . import Status

_PortDecl = Tuple[str, str, str, Optional[str], str]
_Clock = Union["ManualClock", "SystemClock"]

def _bind(status: Any, load_error: type, node_error: type) -> None: ...
def _bind_busy(tree_busy: type) -> None: ...
def _run_scenarios(
    paths: Sequence[str], registry: Optional["Registry"] = None, robot: Any = None
) -> List[Tuple[str, str, float, List[str], str]]:
    """Runs scenario files: per file, its name, file, seconds, problems and report."""

def _merge_campaign_results(sources: Sequence[str], db: str) -> int:
    """Adds the rows of the results files ``sources`` to ``db``: the number added."""

class Campaign:
    """A campaign file (``neurotree campaign run``'s TOML), read and checked."""

    @staticmethod
    def load(path: str) -> "Campaign": ...
    @staticmethod
    def parse(text: str, file: str) -> "Campaign": ...
    @property
    def name(self) -> str: ...
    @property
    def text(self) -> str: ...
    @property
    def file(self) -> str: ...
    @property
    def variants(self) -> int: ...
    def todo(self, db: str, limit: Optional[int] = None, resume: bool = False) -> List[int]: ...
    def run_variants(self, db: str, variants: Sequence[int], threads: int = 0) -> int: ...

class ManualClock:
    """A clock that moves only when told: runs are deterministic and as fast as the ticks."""

    def __init__(self) -> None: ...
    def advance(self, seconds: float) -> None:
        """Moves the clock ``seconds`` forward."""
    def set(self, seconds: float) -> None:
        """Sets the clock to ``seconds``."""
    @property
    def now(self) -> float:
        """The clock's time, in seconds."""

class SystemClock:
    """Wall time since the clock was made."""

    def __init__(self) -> None: ...
    @property
    def now(self) -> float:
        """Seconds since the clock was made."""

class Node:
    """What a Python leaf is handed on each call; valid during that call only."""

    @property
    def name(self) -> str:
        """The node's name (its ``name`` attribute, or its type)."""
    @property
    def path(self) -> str:
        """The node's path in the tree (``"Sequence/MoveTo"``)."""
    @property
    def now(self) -> float:
        """The tree's clock, in seconds."""
    def input(self, port: str) -> Any:
        """Reads input port ``port`` as the type the node type declares; a value that does not
        convert raises ``NodeError`` naming the node and the port."""
    def output(self, port: str, value: Any) -> None:
        """Writes output port ``port``; a value of another type than declared raises
        ``NodeError`` naming the node and the port."""
    def get(self, key: str) -> Any:
        """The blackboard entry ``key`` in the node's scope, or ``None``."""
    def set(self, key: str, value: Any) -> None:
        """Writes the blackboard entry ``key`` in the node's scope."""
    def fail(self, reason: str, code: int = 0) -> Status:
        """Returns ``Status.FAILURE``, giving ``reason`` for ``Tree.last_failure()``."""

class Blackboard:
    """A tree's blackboard (its root scope) as a mapping of ``None``, ``bool``, ``int``,
    ``float``, ``str``, ``list`` and ``dict`` values."""

    def __getitem__(self, key: str) -> Any: ...
    def __setitem__(self, key: str, value: Any) -> None: ...
    def __delitem__(self, key: str) -> None: ...
    def __contains__(self, key: str) -> bool: ...
    def __len__(self) -> int: ...
    def keys(self) -> List[str]:
        """The keys of the root scope, sorted."""
    def get(self, key: str, default: Any = None) -> Any:
        """The entry ``key``, or ``default``."""
    def to_dict(self) -> dict[str, Any]:
        """Every entry, as a dict."""

class Failure:
    """Why the root failed: the chain from the root to the node whose failure decided it."""

    @property
    def path(self) -> str:
        """The node where the chain ends."""
    @property
    def reason(self) -> Optional[str]:
        """The deepest reason given on the chain."""
    @property
    def code(self) -> int:
        """That reason's code (0 without one)."""
    @property
    def chain(self) -> List[Tuple[str, Optional[str]]]:
        """``(path, reason)`` for each node from the root down."""
    @property
    def nodes(self) -> List[Tuple[str, Optional[str]]]:
        """``(path, reason)`` for every node of the failure: the chain's and, below each
        child a Fallback tried, that child's own chain."""

class Coverage:
    """Which outcomes each node has had since ``Tree.start_coverage()``."""

    @property
    def percent(self) -> float:
        """The share of the possible outcomes seen, in percent."""
    def never_reached(self) -> List[str]:
        """The paths of the nodes never reached."""
    def report(self) -> str:
        """The report ``neurotree test --coverage`` prints."""

class Tree:
    """A loaded tree, with its blackboard and clock. Any thread may tick it, one at a time."""

    def tick_once(self, robot: Any = None) -> Status:
        """Ticks once with ``robot`` handed to every leaf; returns the root's ``Status``."""
    def tick_while_running(
        self, robot: Any = None, max_ticks: Optional[int] = None, period: float = 0.01
    ) -> Status:
        """Ticks until the root is not Running, ``period`` seconds apart on the tree's clock;
        ``RUNNING`` if ``max_ticks`` did not finish it. Ctrl-C halts the tree."""
    def halt(self, robot: Any = None) -> None:
        """Halts every Running node."""
    @property
    def blackboard(self) -> Blackboard:
        """The tree's blackboard."""
    @property
    def now(self) -> float:
        """The tree's clock, in seconds."""
    def statuses(self) -> List[Tuple[str, Status]]:
        """``(path, Status)`` of every node, root first."""
    def paths(self) -> List[str]:
        """Every node's path, root first."""
    def last_failure(self) -> Optional[Failure]:
        """Why the root failed on the last tick, or ``None``."""
    def on_status_change(self, callback: Callable[[str, Status, Status, float], object]) -> None:
        """Calls ``callback(path, previous, status, seconds)`` on every status change."""
    def on_trace_line(self, callback: Callable[[str], object]) -> None:
        """Calls ``callback(line)`` with each JSON line ``neurotree run --jsonl`` prints."""
    def start_coverage(self) -> Coverage:
        """Starts recording outcomes per node."""
    def save_state(self) -> bytes:
        """The tree's whole state as bytes."""
    def restore_state(self, state: bytes) -> None:
        """Puts back a state ``save_state`` gave."""
    def reload(
        self,
        xml: Optional[str] = None,
        *,
        path: Union[str, "PathLike[str]", None] = None,
        robot: Any = None,
    ) -> Tuple[int, int, int]:
        """Swaps in a changed tree, keeping the state of unchanged nodes; returns
        ``(kept, restarted, halted)``."""
    def tick_times(self, count: int, robot: Any = None) -> Status:
        """Ticks ``count`` times in one call; returns the last status."""
    def _watch_in_studio(self, port: int = 0, name: str = "tree") -> str: ...

class Registry:
    """Node types by name, and the way from XML to trees."""

    def __init__(self) -> None: ...
    def register_condition(self, name: str, func: Callable[..., Any], ports: Sequence[_PortDecl]) -> None: ...
    def register_action(self, name: str, func: Callable[..., Any], ports: Sequence[_PortDecl]) -> None: ...
    def register_async_action(self, name: str, func: Callable[..., Any], ports: Sequence[_PortDecl]) -> None: ...
    def register_stateful_action(self, name: str, cls: type, ports: Sequence[_PortDecl]) -> None: ...
    def add_nav2(self, release: str = "main") -> None:
        """Adds Nav2's node types of ``release`` (``"jazzy"``, ``"kilted"``, ``"main"``)."""
    def mock(self, name: str, outcomes: str) -> None:
        """Replaces the leaves named (or of type) ``name`` by scripted ``outcomes``."""
    def substitute(self, rules: str, file: str = "<rules>") -> None:
        """Applies BehaviorTree.CPP substitution rules (JSON text) to later loads."""
    def load_string(self, xml: str, clock: Optional[_Clock] = None) -> Tree:
        """Loads XML text; raises ``LoadError``."""
    def load_file(self, path: Union[str, "PathLike[str]"], clock: Optional[_Clock] = None) -> Tree:
        """Loads a file and its includes; raises ``LoadError``."""
    def node_types(self) -> List[str]:
        """The registered node type names, sorted."""
    def tree_nodes_model(self) -> str:
        """The ``TreeNodesModel`` XML of the registered leaves."""

class Builder:
    """Builds a tree node by node: ``open`` a control or decorator, add children, ``close``."""

    def __init__(self) -> None: ...
    def open(self, type_name: str, name: Optional[str] = None, **ports: Any) -> None:
        """Opens the built-in control or decorator ``type_name``, ports as keywords."""
    def close(self) -> None:
        """Closes the node opened last."""
    def leaf(self, type_name: str, name: Optional[str] = None, **ports: Any) -> None:
        """Adds the built-in leaf ``type_name``."""
    def add_condition(self, name: str, func: Callable[..., Any], ports: Sequence[_PortDecl], bind: Optional[dict[str, Any]]) -> None: ...
    def add_action(self, name: str, func: Callable[..., Any], ports: Sequence[_PortDecl], bind: Optional[dict[str, Any]]) -> None: ...
    def add_async_action(self, name: str, func: Callable[..., Any], ports: Sequence[_PortDecl], bind: Optional[dict[str, Any]]) -> None: ...
    def add_stateful_action(self, name: str, cls: type, ports: Sequence[_PortDecl], bind: Optional[dict[str, Any]]) -> None: ...
    def build(self, clock: Optional[_Clock] = None) -> Tree:
        """Checks the tree and returns it; raises ``ValueError`` naming what is wrong."""
