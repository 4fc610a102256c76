//! Reading a `.btlog` back: its tree XML, its first timestamp and its records.

use std::io::{self, Read};
use std::path::Path;
use std::time::Duration;

use neurotree_core::{NodeId, NodeStatus};

use super::{BTLOG_MAGIC, BTLOG_PROTOCOL, RECORD_LEN};
use crate::observe::status_of_code;

/// A `.btlog` as read by [`read_btlog`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Btlog {
    /// The tree, as BehaviorTree.CPP XML with `_uid` attributes.
    pub xml: String,
    /// When the log started, in microseconds since the Unix epoch.
    pub first_timestamp_us: i64,
    /// Every status change, in the order written.
    pub records: Vec<BtlogRecord>,
}

/// One status change in a `.btlog`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BtlogRecord {
    /// Microseconds since the log's first timestamp.
    pub offset_us: u64,
    /// The node's uid: its [`NodeId`] plus one.
    pub uid: u16,
    /// Its new status.
    pub status: NodeStatus,
}

impl BtlogRecord {
    /// The node, for a log written from a NeuroTree blueprint (`None` for uid 0, which no
    /// node has).
    pub fn node(&self) -> Option<NodeId> {
        self.uid.checked_sub(1).map(|i| NodeId(u32::from(i)))
    }

    /// The time since the log's first timestamp.
    pub fn offset(&self) -> Duration {
        Duration::from_micros(self.offset_us)
    }
}

/// Why a `.btlog` could not be read.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum BtlogReadError {
    /// Reading failed.
    #[error("reading the .btlog: {0}")]
    Io(#[from] io::Error),
    /// The data does not start with [`BTLOG_MAGIC`].
    #[error("not a .btlog: it does not start with `BTCPP4-FileLogger2`")]
    BadMagic,
    /// The protocol byte is not [`BTLOG_PROTOCOL`].
    #[error("unknown .btlog protocol {0} (this reader knows protocol 1)")]
    UnsupportedProtocol(u8),
    /// The data ends before a part is complete.
    #[error("the .btlog is cut short: it ends inside {part}, at byte {at}")]
    Truncated {
        /// The part cut short: `the header`, `the tree XML`, `the first timestamp` or `the
        /// last record`.
        part: &'static str,
        /// Where that part starts.
        at: usize,
    },
    /// The XML length is negative.
    #[error("the .btlog gives its tree XML a negative length ({0})")]
    NegativeXmlLength(i32),
    /// The XML is not UTF-8.
    #[error("the tree XML of the .btlog is not UTF-8")]
    XmlNotUtf8,
    /// A record's status is not one BehaviorTree.CPP defines.
    #[error("record {index} (at byte {at}) has status {code}; statuses are 0 to 4")]
    BadStatus {
        /// The record's index, from 0.
        index: usize,
        /// Where it starts.
        at: usize,
        /// The status byte.
        code: u8,
    },
}

neurotree_core::debug_shows_message!(enum BtlogReadError {
    Io(source),
    BadMagic,
    UnsupportedProtocol(source),
    Truncated { part, at },
    NegativeXmlLength(source),
    XmlNotUtf8,
    BadStatus { index, at, code },
});

/// Reads a whole `.btlog` from `input`.
///
/// Every part is checked: the magic, the protocol, that each part is complete (a file cut
/// inside a record is an error, not a shorter log) and that every status is known.
pub fn read_btlog(mut input: impl Read) -> Result<Btlog, BtlogReadError> {
    let mut bytes = Vec::new();
    input.read_to_end(&mut bytes)?;
    parse(&bytes)
}

/// Reads the `.btlog` file at `path`.
pub fn read_btlog_file(path: impl AsRef<Path>) -> Result<Btlog, BtlogReadError> {
    parse(&std::fs::read(path)?)
}

fn parse(bytes: &[u8]) -> Result<Btlog, BtlogReadError> {
    let mut at = 0;
    let magic = take(bytes, &mut at, BTLOG_MAGIC.len(), "the header")?;
    if magic != BTLOG_MAGIC {
        return Err(BtlogReadError::BadMagic);
    }
    let protocol = take(bytes, &mut at, 1, "the header")?[0];
    if protocol != BTLOG_PROTOCOL {
        return Err(BtlogReadError::UnsupportedProtocol(protocol));
    }
    let len = i32::from_le_bytes(take_array(bytes, &mut at, "the header")?);
    let len = usize::try_from(len).map_err(|_| BtlogReadError::NegativeXmlLength(len))?;
    let xml = take(bytes, &mut at, len, "the tree XML")?;
    let xml = String::from_utf8(xml.to_vec()).map_err(|_| BtlogReadError::XmlNotUtf8)?;
    let first_timestamp_us = i64::from_le_bytes(take_array(bytes, &mut at, "the first timestamp")?);

    let body = &bytes[at..];
    if !body.len().is_multiple_of(RECORD_LEN) {
        return Err(BtlogReadError::Truncated {
            part: "the last record",
            at: at + body.len() / RECORD_LEN * RECORD_LEN,
        });
    }
    let records = body
        .chunks_exact(RECORD_LEN)
        .enumerate()
        .map(|(index, r)| {
            let mut offset = [0u8; 8];
            offset[..6].copy_from_slice(&r[..6]);
            let status = status_of_code(r[8]).ok_or(BtlogReadError::BadStatus {
                index,
                at: at + index * RECORD_LEN,
                code: r[8],
            })?;
            Ok(BtlogRecord {
                offset_us: u64::from_le_bytes(offset),
                uid: u16::from_le_bytes([r[6], r[7]]),
                status,
            })
        })
        .collect::<Result<_, BtlogReadError>>()?;
    Ok(Btlog {
        xml,
        first_timestamp_us,
        records,
    })
}

/// The next `n` bytes, or which part was cut short.
fn take<'a>(
    bytes: &'a [u8],
    at: &mut usize,
    n: usize,
    part: &'static str,
) -> Result<&'a [u8], BtlogReadError> {
    let slice = bytes
        .get(*at..)
        .and_then(|rest| rest.get(..n))
        .ok_or(BtlogReadError::Truncated { part, at: *at })?;
    *at += n;
    Ok(slice)
}

fn take_array<const N: usize>(
    bytes: &[u8],
    at: &mut usize,
    part: &'static str,
) -> Result<[u8; N], BtlogReadError> {
    let mut array = [0u8; N];
    array.copy_from_slice(take(bytes, at, N, part)?);
    Ok(array)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A log of `xml` with the given records, as BehaviorTree.CPP lays it out.
    fn log(xml: &str, records: &[([u8; 6], u16, u8)]) -> Vec<u8> {
        let mut out = BTLOG_MAGIC.to_vec();
        out.push(1);
        out.extend_from_slice(&(xml.len() as i32).to_le_bytes());
        out.extend_from_slice(xml.as_bytes());
        out.extend_from_slice(&1_700_000_000_000_000i64.to_le_bytes());
        for (offset, uid, status) in records {
            out.extend_from_slice(offset);
            out.extend_from_slice(&uid.to_le_bytes());
            out.push(*status);
        }
        out
    }

    #[test]
    fn reads_each_field_little_endian() {
        let bytes = log(
            "<root/>",
            &[([1, 2, 3, 0, 0, 0], 0x0102, 2), ([0; 6], 1, 0)],
        );
        let read = read_btlog(&bytes[..]).unwrap();
        assert_eq!(read.xml, "<root/>");
        assert_eq!(read.first_timestamp_us, 1_700_000_000_000_000);
        assert_eq!(
            read.records,
            [
                BtlogRecord {
                    offset_us: 0x030201,
                    uid: 0x0102,
                    status: NodeStatus::Success
                },
                BtlogRecord {
                    offset_us: 0,
                    uid: 1,
                    status: NodeStatus::Idle
                },
            ]
        );
        assert_eq!(read.records[1].node(), Some(NodeId(0)));
        assert_eq!(read.records[0].offset(), Duration::from_micros(0x030201));
    }

    #[test]
    fn a_log_with_no_records_is_fine() {
        let read = read_btlog(&log("<root/>", &[])[..]).unwrap();
        assert!(read.records.is_empty());
    }

    #[test]
    fn every_cut_is_an_error_naming_the_part() {
        let bytes = log("<root/>", &[([0; 6], 1, 1)]);
        let xml_at = 18 + 1 + 4;
        let stamp_at = xml_at + 7;
        let record_at = stamp_at + 8;
        assert_eq!(bytes.len(), record_at + 9);
        for cut in 0..bytes.len() {
            if cut == record_at {
                continue; // A log with no records.
            }
            let err = read_btlog(&bytes[..cut]).unwrap_err();
            let (part, at) = match err {
                BtlogReadError::Truncated { part, at } => (part, at),
                other => panic!("cut at {cut}: {other}"),
            };
            let expected = if cut < xml_at {
                "the header"
            } else if cut < stamp_at {
                "the tree XML"
            } else if cut < record_at {
                "the first timestamp"
            } else {
                "the last record"
            };
            assert_eq!(part, expected, "cut at {cut}");
            assert!(at <= cut, "cut at {cut}: part said to start at {at}");
        }
    }

    #[test]
    fn bad_magic_protocol_length_and_status_are_errors() {
        let good = log("<root/>", &[([0; 6], 1, 1)]);

        let mut bad = good.clone();
        bad[0] = b'X';
        assert!(matches!(
            read_btlog(&bad[..]),
            Err(BtlogReadError::BadMagic)
        ));

        let mut bad = good.clone();
        bad[18] = 2;
        assert!(matches!(
            read_btlog(&bad[..]),
            Err(BtlogReadError::UnsupportedProtocol(2))
        ));

        let mut bad = good.clone();
        bad[19..23].copy_from_slice(&(-1i32).to_le_bytes());
        assert!(matches!(
            read_btlog(&bad[..]),
            Err(BtlogReadError::NegativeXmlLength(-1))
        ));

        let mut bad = good.clone();
        let last = bad.len() - 1;
        bad[last] = 9;
        let err = read_btlog(&bad[..]).unwrap_err();
        assert!(matches!(
            err,
            BtlogReadError::BadStatus {
                index: 0,
                code: 9,
                ..
            }
        ));
        assert!(err.to_string().contains("status 9"));

        let mut bad = good;
        bad[23] = 0xff;
        assert!(matches!(
            read_btlog(&bad[..]),
            Err(BtlogReadError::XmlNotUtf8)
        ));
    }
}
