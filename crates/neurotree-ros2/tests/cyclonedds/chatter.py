"""The other side of the Cyclone DDS interoperability test (`tests/cyclonedds.rs`).

Eclipse Cyclone DDS, through its Python binding, plays a ROS 2 node on the topic `chatter`
(DDS topic `rt/chatter`, type `std_msgs::msg::dds_::String_`): it publishes
"hello from cyclonedds N" every 100 ms and reads the topic until a message that begins with
"hello from neurotree" arrives, which it prints before exiting 0; it exits 1 when none came
within the time limit.

Usage: chatter.py DOMAIN_ID SECONDS. Discovery is unicast on 127.0.0.1 only (see the
configuration below), as NeuroTree's own participants do.
"""

import os
import sys
import time
from dataclasses import dataclass

domain_id = int(sys.argv[1])
seconds = float(sys.argv[2])

# Loopback only, no multicast: SPDP goes to the well-known unicast ports of 127.0.0.1.
os.environ["CYCLONEDDS_URI"] = """<CycloneDDS><Domain id="any">
  <General>
    <Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
    <AllowMulticast>false</AllowMulticast>
  </General>
  <Discovery>
    <ParticipantIndex>auto</ParticipantIndex>
    <MaxAutoParticipantIndex>20</MaxAutoParticipantIndex>
    <Peers><Peer address="127.0.0.1"/></Peers>
  </Discovery>
</Domain></CycloneDDS>"""

from cyclonedds.core import Policy, Qos  # noqa: E402
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.idl import IdlStruct  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.sub import DataReader  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402
from cyclonedds.util import duration  # noqa: E402


@dataclass
class String_(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    data: str


# ROS 2's default QoS: reliable, volatile, keep the last 10.
qos = Qos(
    Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
    Policy.Durability.Volatile,
    Policy.History.KeepLast(10),
)
participant = DomainParticipant(domain_id)
topic = Topic(participant, "rt/chatter", String_, qos=qos)
writer = DataWriter(participant, topic, qos=qos)
reader = DataReader(participant, topic, qos=qos)

deadline = time.monotonic() + seconds
count = 0
while time.monotonic() < deadline:
    count += 1
    writer.write(String_(data=f"hello from cyclonedds {count}"))
    for sample in reader.take(N=100):
        if sample.data.startswith("hello from neurotree"):
            print(f"received: {sample.data}", flush=True)
            sys.exit(0)
    time.sleep(0.1)
print("no message from neurotree", flush=True)
sys.exit(1)
