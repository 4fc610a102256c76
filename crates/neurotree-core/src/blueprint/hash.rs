//! A blueprint's structure hash: what a saved state names its tree by.

use super::Blueprint;

impl<C> Blueprint<C> {
    /// A hash of the tree's structure: every node's type, parameters, name, children and
    /// port bindings, in order. Two blueprints built alike have the same hash, in any
    /// process and on any machine; a saved state names its tree by it
    /// ([`crate::state`]). User closures and objects count by their kind, not their code.
    pub fn structure_hash(&self) -> u64 {
        #[cfg(target_has_atomic = "64")]
        {
            use core::sync::atomic::Ordering;
            let known = self.hash.load(Ordering::Relaxed);
            if known != 0 {
                return known;
            }
            // 0 marks "not yet": a structure that hashes to 0 is taken as 1.
            let hash = self.compute_structure_hash().max(1);
            self.hash.store(hash, Ordering::Relaxed);
            hash
        }
        #[cfg(not(target_has_atomic = "64"))]
        self.compute_structure_hash().max(1)
    }

    /// [`structure_hash`](Self::structure_hash), made from the nodes.
    fn compute_structure_hash(&self) -> u64 {
        use core::fmt::Write;
        let mut h = Fnv(0xcbf2_9ce4_8422_2325);
        for id in self.ids() {
            let def = self.def(id);
            // Writing into the hash cannot fail.
            let _ = write!(
                h,
                "{}\u{1}{:?}\u{1}{}\u{1}{}\u{1}",
                self.type_id(id),
                def.kind,
                self.name(id),
                def.child_count
            );
            for port in self.ports(id) {
                let _ = write!(h, "{}={:?}\u{1}", port.name, port.value);
            }
            let _ = h.write_str("\u{2}");
        }
        h.0
    }
}

/// FNV-1a, 64 bits: a hash that is the same in every process and release, as a saved
/// state's reference to its tree must be.
struct Fnv(u64);

impl core::fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for &byte in s.as_bytes() {
            self.0 ^= u64::from(byte);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
        Ok(())
    }
}
