//! The stream's pipes: one thread reads frames from stdin into a small queue, another writes
//! composites to stdout, and the GPU loop runs between them. By default the queue holds two
//! frames and the reader waits when it is full (lossless: the source is slowed down); with
//! `--drop-late` it holds the newest frame only, and a frame replaced before the GPU loop took
//! it is dropped and counted.

use std::collections::VecDeque;
use std::io::{ErrorKind, Read, Write};
use std::sync::mpsc::{SyncSender, sync_channel};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Instant;

/// Frames read ahead of the GPU loop when every frame is kept.
const QUEUE_FRAMES: usize = 2;
/// Composites waiting for the writer.
const WRITE_QUEUE_FRAMES: usize = 2;

/// One frame, in or out.
pub struct Frame {
    /// Its number in the input, from 0 (dropped frames count).
    pub index: u64,
    /// `width × height × 3` bytes of RGB.
    pub rgb: Vec<u8>,
    /// When its last byte was read: latency is measured from here.
    pub read_at: Instant,
}

/// How the input ended.
pub enum End {
    /// End of file at a frame boundary.
    Clean,
    /// End of file inside frame `index`, after `got` of its bytes.
    Truncated {
        /// The frame's number.
        index: u64,
        /// Bytes read of it.
        got: usize,
    },
    /// A read error.
    Failed(std::io::Error),
}

/// What the reader thread shares with the GPU loop.
#[derive(Default)]
struct Queue {
    frames: VecDeque<Frame>,
    end: Option<End>,
    read: u64,
    dropped: u64,
}

/// Frames from a reader thread.
pub struct Reader {
    shared: Arc<(Mutex<Queue>, Condvar)>,
}

impl Reader {
    /// Starts a thread reading frames of `frame_bytes` from `input`, keeping only the newest
    /// when `newest_only`. The thread is not joined: a live source may never end, and the
    /// process exits without waiting for it.
    pub fn start(mut input: impl Read + Send + 'static, frame_bytes: usize, newest_only: bool) -> Self {
        let shared = Arc::new((Mutex::new(Queue::default()), Condvar::new()));
        let theirs = Arc::clone(&shared);
        std::thread::spawn(move || {
            let (queue, changed) = &*theirs;
            for index in 0.. {
                let mut rgb = vec![0u8; frame_bytes];
                let got = match read_full(&mut input, &mut rgb) {
                    Ok(got) => got,
                    Err(e) => return close(queue, changed, End::Failed(e)),
                };
                if got < frame_bytes {
                    return close(queue, changed, if got == 0 { End::Clean } else { End::Truncated { index, got } });
                }
                let mut q = lock(queue);
                if newest_only {
                    q.dropped += q.frames.len() as u64;
                    q.frames.clear();
                } else {
                    while q.frames.len() >= QUEUE_FRAMES {
                        q = changed.wait(q).unwrap_or_else(|e| e.into_inner());
                    }
                }
                q.frames.push_back(Frame { index, rgb, read_at: Instant::now() });
                q.read += 1;
                changed.notify_all();
            }
        });
        Self { shared }
    }

    /// The next frame to render, waiting for it; `None` once the input has ended.
    pub fn next(&self) -> Option<Frame> {
        let (queue, changed) = &*self.shared;
        let mut q = lock(queue);
        loop {
            if let Some(frame) = q.frames.pop_front() {
                changed.notify_all();
                return Some(frame);
            }
            if q.end.is_some() {
                return None;
            }
            q = changed.wait(q).unwrap_or_else(|e| e.into_inner());
        }
    }

    /// How the input ended (`None` before it has).
    pub fn end(&self) -> Option<End> {
        lock(&self.shared.0).end.take()
    }

    /// Frames read so far, and how many of them were dropped.
    pub fn counts(&self) -> (u64, u64) {
        let q = lock(&self.shared.0);
        (q.read, q.dropped)
    }
}

fn lock(queue: &Mutex<Queue>) -> MutexGuard<'_, Queue> {
    queue.lock().unwrap_or_else(|e| e.into_inner())
}

fn close(queue: &Mutex<Queue>, changed: &Condvar, end: End) {
    lock(queue).end = Some(end);
    changed.notify_all();
}

/// Fills `buf` from `input` as far as it goes: the bytes read, fewer only at the end.
fn read_full(input: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match input.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}

/// Composites to a writer thread.
pub struct Writer {
    frames: SyncSender<Frame>,
    thread: JoinHandle<std::io::Result<Vec<f64>>>,
}

impl Writer {
    /// Starts a thread writing frames to `output`, each flushed as it comes (a live viewer
    /// shows it at once).
    pub fn start(mut output: impl Write + Send + 'static) -> Self {
        let (frames, queue) = sync_channel::<Frame>(WRITE_QUEUE_FRAMES);
        let thread = std::thread::spawn(move || {
            let mut latencies_ms = Vec::new();
            for frame in queue {
                output.write_all(&frame.rgb)?;
                output.flush()?;
                latencies_ms.push(frame.read_at.elapsed().as_secs_f64() * 1e3);
            }
            Ok(latencies_ms)
        });
        Self { frames, thread }
    }

    /// Queues `frame`, waiting while the writer is behind; `false` once the writer has
    /// stopped (its error comes from [`Writer::finish`]).
    pub fn send(&self, frame: Frame) -> bool {
        self.frames.send(frame).is_ok()
    }

    /// Writes what is queued and stops: each written frame's latency, from its read to its
    /// write, in milliseconds.
    pub fn finish(self) -> std::io::Result<Vec<f64>> {
        drop(self.frames);
        self.thread.join().unwrap_or_else(|_| Err(std::io::Error::other("the writer thread panicked")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(input: Vec<u8>, frame_bytes: usize, newest_only: bool) -> (Vec<Vec<u8>>, Option<End>) {
        let reader = Reader::start(std::io::Cursor::new(input), frame_bytes, newest_only);
        let mut out = Vec::new();
        while let Some(f) = reader.next() {
            out.push(f.rgb);
        }
        (out, reader.end())
    }

    #[test]
    fn frames_end_cleanly_or_truncated() {
        let (out, end) = frames((0..12).collect(), 6, false);
        assert_eq!(out, vec![(0..6).collect::<Vec<u8>>(), (6..12).collect()]);
        assert!(matches!(end, Some(End::Clean)));
        let (out, end) = frames((0..14).collect(), 6, false);
        assert_eq!(out.len(), 2);
        assert!(matches!(end, Some(End::Truncated { index: 2, got: 2 })));
        let (out, end) = frames(Vec::new(), 6, false);
        assert!(out.is_empty() && matches!(end, Some(End::Clean)));
    }

    #[test]
    fn newest_only_drops_what_waits() {
        let reader = Reader::start(std::io::Cursor::new(vec![7u8; 30]), 3, true);
        // Let the reader finish before taking anything: only the last frame is left.
        while reader.counts().0 < 10 {
            std::thread::yield_now();
        }
        let last = reader.next().unwrap();
        assert_eq!((last.index, reader.next().is_none()), (9, true));
        assert_eq!(reader.counts(), (10, 9));
    }

    #[test]
    fn the_writer_reports_a_closed_output() {
        struct Closed;
        impl Write for Closed {
            fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
                Err(ErrorKind::BrokenPipe.into())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let writer = Writer::start(Closed);
        let _ = writer.send(Frame { index: 0, rgb: vec![1, 2, 3], read_at: Instant::now() });
        assert_eq!(writer.finish().unwrap_err().kind(), ErrorKind::BrokenPipe);
    }
}
