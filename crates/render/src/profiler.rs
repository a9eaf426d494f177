//! GPU pass timings with timestamp queries. Every pass asks for a slot by name; after the frame's
//! submission, [`GpuProfiler::read`] returns (name, milliseconds) per slot. Without
//! `TIMESTAMP_QUERY` the profiler hands out no timestamp writes and reads nothing.
//!
//! A frame's first timed pass ([`GpuProfiler::lead`], named [`LEAD`]) is empty: a first
//! timestamp can be written while the GPU still works on what was submitted before, or take the
//! queue's start-up, and the first real pass (the G-buffer) would read that wait as its own
//! time. The lead absorbs it; [`frame_total`] leaves it out (docs/src/results.md, "Costs").

/// Most timed passes per frame.
pub const MAX_PASSES: u32 = 64;

/// The name of the empty pass timed first in each frame.
pub const LEAD: &str = "lead";

/// A frame's GPU time: the sum of its passes' times, the [`LEAD`] left out.
pub fn frame_total(timings: &[(&'static str, f64)]) -> f64 {
    timings
        .iter()
        .filter(|(name, _)| *name != LEAD)
        .map(|(_, ms)| ms)
        .sum()
}

pub struct GpuProfiler {
    queries: Option<wgpu::QuerySet>,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    labels: Vec<&'static str>,
    period_ns: f32,
}

impl GpuProfiler {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, enabled: bool) -> Self {
        let queries = enabled.then(|| {
            device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_PASSES,
            })
        });
        let size = 8 * 2 * MAX_PASSES as u64;
        GpuProfiler {
            queries,
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            labels: Vec::new(),
            period_ns: queue.get_timestamp_period(),
        }
    }

    pub fn enabled(&self) -> bool {
        self.queries.is_some()
    }

    /// Starts a new frame's list of slots.
    pub fn begin_frame(&mut self) {
        self.labels.clear();
    }

    fn slot(&mut self, label: &'static str) -> Option<(&wgpu::QuerySet, u32)> {
        let q = self.queries.as_ref()?;
        if self.labels.len() as u32 >= MAX_PASSES {
            return None;
        }
        self.labels.push(label);
        Some((q, 2 * (self.labels.len() as u32 - 1)))
    }

    /// Encodes the frame's [`LEAD`]: an empty compute pass, timed, before every other pass
    /// (nothing without timestamps).
    pub fn lead(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if !self.enabled() {
            return;
        }
        let timestamp_writes = self.compute(LEAD);
        drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(LEAD),
            timestamp_writes,
        }));
    }

    /// Timestamp writes for a compute pass named `label`.
    pub fn compute(&mut self, label: &'static str) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.slot(label)
            .map(|(q, i)| wgpu::ComputePassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Timestamp writes for a render pass named `label`.
    pub fn render(&mut self, label: &'static str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.slot(label)
            .map(|(q, i)| wgpu::RenderPassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Timestamp writes for a group of render passes timed as one: the first pass writes the
    /// beginning, the last the end. Call with `first`/`last` flags for each pass of the group.
    pub fn render_group(
        &mut self,
        label: &'static str,
        first: bool,
        last: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        if first {
            self.slot(label)?;
        } else if !last {
            // Passes in the middle of the group write no timestamp (wgpu requires at least one
            // index when timestamp writes are given).
            return None;
        }
        let i = 2 * (self.labels.len() as u32).checked_sub(1)?;
        let q = self.queries.as_ref()?;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: q,
            beginning_of_pass_write_index: first.then_some(i),
            end_of_pass_write_index: last.then_some(i + 1),
        })
    }

    /// Copies this frame's timestamps into the readback buffer (encode after all passes).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(q) = &self.queries
            && !self.labels.is_empty()
        {
            let n = 2 * self.labels.len() as u32;
            encoder.resolve_query_set(q, 0..n, &self.resolve, 0);
            encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, 8 * n as u64);
        }
    }

    /// Reads the last resolved frame (blocks until the GPU is done): (pass, milliseconds).
    pub fn read(&self, device: &wgpu::Device) -> Vec<(&'static str, f64)> {
        if self.queries.is_none() || self.labels.is_empty() {
            return Vec::new();
        }
        let n = 2 * self.labels.len() as u64;
        let slice = self.readback.slice(0..8 * n);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        let ticks: Vec<u64> =
            bytemuck::cast_slice(&slice.get_mapped_range().expect("mapped")).to_vec();
        self.readback.unmap();
        self.labels
            .iter()
            .enumerate()
            .map(|(i, &l)| {
                let dt = ticks[2 * i + 1].saturating_sub(ticks[2 * i]);
                (l, dt as f64 * self.period_ns as f64 * 1e-6)
            })
            .collect()
    }
}
