//! Every cut layer of a build placed by its [`Packing`], the irregular nester working on
//! several layers at once while its observer hears of them in order.

use super::irregular::irregular;
use super::packing::{NestObserver, Packing};
use super::shelf::shelf;
use super::PlacedLayer;
use crate::pipeline::cut::CutLayer;
use crate::pipeline::jobs::Names;
use crate::pipeline::BuildError;
use cam_nest::NestProgress;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Lay out a cut layer with the build's packing strategy and verify it.
fn place_cut_layer(
    layer: &CutLayer,
    packing: &Packing<'_>,
    names: &Names,
) -> Result<PlacedLayer, BuildError> {
    match packing {
        Packing::Shelf => Ok(PlacedLayer {
            layouts: shelf(layer, names)?,
            baseline: None,
            strip_length_mm: None,
            drawn: Vec::new(),
        }),
        Packing::Irregular(opts, observer) => {
            let deadline = opts.time.map(|t| t.share(1, 1));
            irregular(layer, opts, deadline, *observer, names)
        }
    }
}

/// Cut layers the irregular nester works on at once. Each nest has its own `WORKERS` threads;
/// with two at a time the cores stay busy while one nest waits for its slower worker, and a
/// small layer is nested beside a large one instead of after it.
const LAYERS_AT_ONCE: usize = 2;

/// What a layer nested on another thread tells the thread that runs the build: a progress
/// report, or `None` once it is placed.
type Relayed = (usize, Option<NestProgress>);

/// The observer of a layer nested on another thread: sends its reports to the build's thread.
struct Forward {
    index: usize,
    to: std::sync::mpsc::Sender<Relayed>,
}

impl NestObserver for Forward {
    fn layer(&self, _: usize, _: usize, _: &str, _: usize) {}
    fn progress(&self, progress: &NestProgress) {
        // The receiver lives until every layer is placed; a send cannot fail before that.
        let _ = self.to.send((self.index, Some(*progress)));
    }
}

/// Lay out and verify every cut layer ([`place_cut_layer`]), results in layer order. The
/// irregular nester works on `LAYERS_AT_ONCE` layers at once; its observer still hears of the
/// layers one after the other, as if they were nested in order (a layer's reports wait until
/// the layers before it are placed), on the thread that runs the build. A layout never depends
/// on this: each nest is a function of its layer and the seed.
pub(crate) fn place_cut_layers(
    layers: &[CutLayer],
    packing: &Packing<'_>,
    names: &Names,
) -> Vec<Result<PlacedLayer, BuildError>> {
    let Packing::Irregular(opts, observer) = packing else {
        return layers
            .iter()
            .map(|layer| place_cut_layer(layer, packing, names))
            .collect();
    };
    let count = layers.len();
    let announce = |index: usize| {
        let layer = &layers[index];
        let copies = layer.items.iter().map(|i| i.count).sum();
        observer.layer(index, count, &layer.layer, copies);
    };
    let next = AtomicUsize::new(0);
    let placed: Mutex<Vec<Option<Result<PlacedLayer, BuildError>>>> =
        Mutex::new((0..count).map(|_| None).collect());
    let (to, relayed) = std::sync::mpsc::channel::<Relayed>();
    std::thread::scope(|scope| {
        for _ in 0..LAYERS_AT_ONCE.min(count) {
            let (to, next, placed) = (to.clone(), &next, &placed);
            scope.spawn(move || loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                if index >= count {
                    break;
                }
                let forward = Forward {
                    index,
                    to: to.clone(),
                };
                let deadline = opts.time.map(|t| t.share(count - index, LAYERS_AT_ONCE));
                let result = irregular(&layers[index], opts, deadline, &forward, names);
                placed.lock().expect("no thread panics holding it")[index] = Some(result);
                let _ = to.send((index, None));
            });
        }
        drop(to);
        // Relay in layer order: the current layer's reports at once, later layers' held back.
        let mut held: Vec<Vec<NestProgress>> = vec![Vec::new(); count];
        let mut done = vec![false; count];
        let mut current = 0;
        if count > 0 {
            announce(0);
        }
        for (index, report) in relayed {
            match report {
                Some(p) if index == current => observer.progress(&p),
                Some(p) => held[index].push(p),
                None => done[index] = true,
            }
            while current < count && done[current] {
                current += 1;
                if current < count {
                    announce(current);
                    for p in held[current].drain(..) {
                        observer.progress(&p);
                    }
                }
            }
        }
    });
    placed
        .into_inner()
        .expect("no thread panicked")
        .into_iter()
        .map(|r| r.expect("every layer placed"))
        .collect()
}
