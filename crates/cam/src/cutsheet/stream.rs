//! A cut sheet planned, rendered and handed to the output writer drawing by drawing, for quantities
//! whose files would not fit in memory together (q = 20000 makes about 57 000 files, 1.1 GB).
//!
//! The build runs on the calling thread and hands each drawing on as soon as it is made; render
//! workers turn drawings into SVG/DXF bytes on the other cores; one writer puts the files in drawing
//! order, so the bytes and the report's file list are those of [`super::write::render`]. At most
//! [`IN_FLIGHT`] drawings are between the build and the writer at any time: memory holds that many
//! drawings and their bytes, plus the report, whatever the quantity.

use super::write::{render_drawing, svg_options, RenderError};
use super::{plan_into, CutSheet, CutSheetOptions, SheetDrawing, Template};
use crate::design::Design;
use crate::pipeline::{BuildError, SinkError};
use std::collections::BTreeMap;
use std::sync::mpsc::{sync_channel, Receiver};
use std::sync::Mutex;

/// Drawings made but not yet written, at most. Enough to keep the workers busy while one renders a
/// large passive sheet (about 20 ms against 1 ms for a clamp-panel layer).
pub const IN_FLIGHT: usize = 32;

/// Where the files go, in drawing order: `put(name, bytes)`.
pub type FilePut<'a> = dyn FnMut(&str, &[u8]) -> Result<(), SinkError> + Send + 'a;

/// Rendered files of one drawing, by its index in file order.
type Rendered = (usize, Result<Vec<(String, Vec<u8>)>, RenderError>);

/// Plan the cut sheet of `design` and hand every layer file to `put` as it is rendered, in file order.
/// Returns the cut sheet (without drawings: they are gone) and the names of the files put, for the
/// report ([`super::write::render_report`]).
pub fn plan_and_put(
    design: &Design,
    template: &Template,
    opts: &CutSheetOptions,
    put: &mut FilePut<'_>,
) -> Result<(CutSheet, Vec<String>), BuildError> {
    let svg = svg_options(&template.palette, opts.stroke_mm);
    let formats = opts.formats;
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (job_tx, job_rx) = sync_channel::<(usize, SheetDrawing)>(IN_FLIGHT);
    let job_rx = Mutex::new(job_rx);
    std::thread::scope(|scope| {
        let (done_tx, done_rx) = sync_channel::<Rendered>(IN_FLIGHT);
        // Tokens: the build takes one per drawing, the writer gives it back once the drawing is written.
        let (slot_tx, slot_rx) = sync_channel::<()>(IN_FLIGHT);
        for _ in 0..IN_FLIGHT {
            slot_tx.send(()).expect("room for every token");
        }
        for _ in 0..workers {
            let done_tx = done_tx.clone();
            let (job_rx, svg) = (&job_rx, &svg);
            scope.spawn(move || loop {
                let job = job_rx.lock().unwrap_or_else(|e| e.into_inner()).recv();
                let Ok((index, drawing)) = job else { break };
                let files = render_drawing(&drawing, formats, svg);
                drop(drawing);
                if done_tx.send((index, files)).is_err() {
                    break;
                }
            });
        }
        drop(done_tx);
        let writer = scope.spawn(move || write_in_order(done_rx, slot_tx, put));

        let mut next = 0;
        let mut sink = |drawing: SheetDrawing| -> Result<(), SinkError> {
            // No token: the writer stopped, and its error is the one reported.
            slot_rx.recv().map_err(|_| "the writer stopped")?;
            job_tx
                .send((next, drawing))
                .map_err(|_| "the render workers stopped")?;
            next += 1;
            Ok(())
        };
        let planned = plan_into(design, template, opts, Some(&mut sink));
        drop(job_tx);
        let written = writer
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e));
        // A failed write is the cause of any failure of the sink: report it first.
        let names = written.map_err(BuildError::Sink)?;
        Ok((planned?, names))
    })
}

/// The writer: put each drawing's files in index order as they arrive, returning a token per drawing.
fn write_in_order(
    done: Receiver<Rendered>,
    slots: std::sync::mpsc::SyncSender<()>,
    put: &mut FilePut<'_>,
) -> Result<Vec<String>, SinkError> {
    let mut waiting = BTreeMap::new();
    let mut next = 0;
    let mut names = Vec::new();
    for (index, files) in done {
        waiting.insert(index, files);
        while let Some(files) = waiting.remove(&next) {
            for (name, bytes) in files? {
                put(&name, &bytes)?;
                names.push(name);
            }
            next += 1;
            // The build may be done and gone: a token nobody takes is fine.
            let _ = slots.send(());
        }
    }
    Ok(names)
}
