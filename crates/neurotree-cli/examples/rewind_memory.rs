//! What the studio's rewind window costs in memory: the heap a watched run holds at its end
//! with a window of N ticks, less the heap the same run holds with none (`--rewind-window
//! 0`), for tree1111 (1,000 ticks) and for the Nav2 demo (its whole run).
//!
//! ```sh
//! cargo run --release -p neurotree-cli --example rewind_memory -- 300
//! ```
//!
//! A counting allocator measures the live heap; no page is attached (the window keeps the
//! states all the same, so that a page that comes later can go back).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

use neurotree::scene::Scene;
use neurotree::sim::nav2::Nav2Sim;
use neurotree::state::StateCodecs;
use neurotree::{ManualClock, Tree};
use neurotree_cli::demo::{DemoConfig, DemoRun, DemoSaved, DemoWorld};
use neurotree_studio::{Studio, StudioOptions, World};

struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);

// SAFETY: every call is passed to the system allocator unchanged; only sizes are counted.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as isize, Ordering::Relaxed);
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LIVE.fetch_add(
            new_size as isize - layout.size() as isize,
            Ordering::Relaxed,
        );
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn live() -> isize {
    LIVE.load(Ordering::Relaxed)
}

/// The demo's world as `demo --studio` keeps it.
struct Warehouse<'a>(DemoWorld<'a>);

impl World<Nav2Sim> for Warehouse<'_> {
    type Saved = DemoSaved;
    fn save(&self, _: &Tree<Nav2Sim>) -> Result<DemoSaved, String> {
        Ok(self.0.save())
    }
    fn restore(&mut self, saved: &DemoSaved) {
        self.0.restore(saved);
    }
    fn codecs(&self) -> StateCodecs {
        DemoWorld::codecs()
    }
    fn scene(&self, tree: &Tree<Nav2Sim>) -> Option<Scene> {
        Some(self.0.scene(tree))
    }
}

/// Live heap after 1,000 ticks of tree1111 watched with a window of `window`, and the bytes
/// of the tree states kept.
fn tree1111(studio: &Studio, window: usize) -> (isize, usize) {
    let before = live();
    let blueprint = neurotree_bench::tree1111_xml::<()>();
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    let (observer, watch) = studio.attach(&tree, "tree1111.xml");
    tree.set_observer(observer);
    let mut watch = watch.rewind_window(window);
    for _ in 0..1000 {
        watch.between_ticks(&mut tree);
        tree.tick_once(&mut ()).expect("tree1111 ticks");
    }
    watch.between_ticks(&mut tree);
    let held = live() - before;
    let kept = watch.rewind_bytes();
    drop((watch, tree));
    (held, kept)
}

/// Live heap at the end of the demo watched with a window of `window`, its ticks, and the
/// bytes of the tree states kept.
fn demo(studio: &Studio, window: usize) -> (isize, u32, usize) {
    let before = live();
    let mut demo = DemoRun::new(&DemoConfig::default()).expect("the demo loads");
    let (observer, watch) = studio.attach(demo.tree_mut(), "nav2.xml");
    demo.add_observer(Box::new(observer));
    let mut watch = watch.rewind_window(window);
    while !demo.is_over() {
        let (tree, world) = demo.watched();
        watch.between_ticks_with(tree, &mut Warehouse(world));
        demo.tick();
    }
    let (tree, world) = demo.watched();
    watch.between_ticks_with(tree, &mut Warehouse(world));
    let held = live() - before;
    let kept = watch.rewind_bytes();
    let ticks = demo.ticks();
    drop((watch, demo));
    (held, ticks, kept)
}

fn main() {
    let window: usize = std::env::args()
        .nth(1)
        .and_then(|n| n.parse().ok())
        .unwrap_or(300);
    let studio = Studio::serve(StudioOptions::default(), neurotree::Registry::new)
        .expect("the studio serves");
    let kib = |b: isize| b as f64 / 1024.0;
    let (none, _) = tree1111(&studio, 0);
    let (with, kept) = tree1111(&studio, window);
    println!(
        "tree1111, 1000 ticks: window {window}: {:.0} KiB more than no window ({:.1} KiB a tick); tree states {:.0} KiB",
        kib(with - none),
        kib(with - none) / window.min(1001) as f64,
        kib(kept as isize)
    );
    let (none, ticks, _) = demo(&studio, 0);
    let (with, _, kept) = demo(&studio, window);
    println!(
        "Nav2 demo, {ticks} ticks: window {window}: {:.0} KiB more than no window ({:.1} KiB a tick); tree states {:.0} KiB",
        kib(with - none),
        kib(with - none) / window.min(ticks as usize + 1) as f64,
        kib(kept as isize)
    );
}
