//! Pass timing: GPU timestamps around each pass where the adapter has TIMESTAMP_QUERY, the wall
//! clock (the GPU waited for after each part) elsewhere.

use std::time::Instant;

use crate::resources::Resources;
use crate::{Gpu, RenderError};

/// Where a frame's times come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimingSource {
    /// GPU timestamps written at the start and end of each pass.
    #[default]
    GpuTimestamps,
    /// The wall clock around each part, the GPU waited for after it.
    WallClock,
}

impl TimingSource {
    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            TimingSource::GpuTimestamps => "GPU timestamps",
            TimingSource::WallClock => "wall clock",
        }
    }
}

/// Which part of the frame a pass belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Part {
    Shadow,
    Main,
}

const MAX_QUERIES: u32 = 256;

/// Timestamp queries: a pair per pass, resolved at the end of the frame.
pub(crate) struct Timer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
    parts: Vec<Part>,
}

impl Timer {
    /// A timer where the device has timestamps.
    pub fn new(gpu: &Gpu, resources: &Resources) -> Option<Self> {
        if !gpu
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
        {
            return None;
        }
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: MAX_QUERIES,
        });
        let size = 8 * MAX_QUERIES as u64;
        Some(Self {
            queries,
            resolve: resources.buffer(
                "timestamps",
                size,
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: resources.buffer(
                "timestamps readback",
                size,
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ),
            period_ns: gpu.queue.get_timestamp_period() as f64,
            parts: Vec::with_capacity(MAX_QUERIES as usize / 2),
        })
    }

    pub fn begin_frame(&mut self) {
        self.parts.clear();
    }

    /// The timestamp writes of the next pass of `part` (none once the queries run out).
    pub fn pass(&mut self, part: Part) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let k = self.parts.len() as u32;
        if 2 * k + 2 > MAX_QUERIES {
            return None;
        }
        self.parts.push(part);
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * k),
            end_of_pass_write_index: Some(2 * k + 1),
        })
    }

    /// Resolves this frame's queries (at the end of its last encoder).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let n = 2 * self.parts.len() as u32;
        if n == 0 {
            return;
        }
        encoder.resolve_query_set(&self.queries, 0..n, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, 8 * n as u64);
    }

    /// Milliseconds per part, after the frame's submission has finished.
    pub fn read(&self, gpu: &Gpu) -> Result<(f64, f64), RenderError> {
        let n = 2 * self.parts.len() as u64;
        if n == 0 {
            return Ok((0.0, 0.0));
        }
        let slice = self.readback.slice(..8 * n);
        crate::readback::map_for_reading(gpu, &slice)?;
        let mut sums = (0.0, 0.0);
        {
            let data = slice
                .get_mapped_range()
                .map_err(|e| RenderError::Gpu(e.to_string()))?;
            let stamps: &[u64] = bytemuck::cast_slice(&data);
            for (k, part) in self.parts.iter().enumerate() {
                let ticks = stamps[2 * k + 1].saturating_sub(stamps[2 * k]);
                let ms = ticks as f64 * self.period_ns * 1e-6;
                match part {
                    Part::Shadow => sums.0 += ms,
                    Part::Main => sums.1 += ms,
                }
            }
        }
        self.readback.unmap();
        Ok(sums)
    }
}

/// Times of one frame's parts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timings {
    /// The shadow part (depth passes; for volumes, extrusion and stencil passes), ms.
    pub shadow_pass_ms: f64,
    /// The main pass(es), ms.
    pub main_pass_ms: f64,
    /// Reading the images back, ms (wall clock).
    pub readback_ms: f64,
    /// Where the pass times come from.
    pub source: TimingSource,
}

/// A frame's encoder and its part times: with GPU timestamps one submission and the passes'
/// own times; without, a submission and a wait after each part, timed by the wall clock.
pub(crate) struct FrameClock {
    encoder: wgpu::CommandEncoder,
    gpu_timed: bool,
    part_start: Instant,
    cpu_shadow_ms: f64,
    wall: (f64, f64),
}

impl FrameClock {
    /// Starts a frame: timed by `timer` where `gpu_timed`, else by the wall clock.
    pub fn start(gpu: &Gpu, timer: &mut Option<Timer>, gpu_timed: bool) -> Self {
        if let Some(timer) = timer {
            timer.begin_frame();
        }
        Self {
            encoder: gpu.device.create_command_encoder(&Default::default()),
            gpu_timed,
            part_start: Instant::now(),
            cpu_shadow_ms: 0.0,
            wall: (0.0, 0.0),
        }
    }

    pub fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        &mut self.encoder
    }

    /// The timestamp writes of the next pass, when timed on the GPU.
    pub fn timestamps<'t>(
        &self,
        timer: &'t mut Option<Timer>,
        part: Part,
    ) -> Option<wgpu::RenderPassTimestampWrites<'t>> {
        if self.gpu_timed {
            timer.as_mut()?.pass(part)
        } else {
            None
        }
    }

    /// Ends CPU work that belongs to the shadow part (volume extrusion).
    pub fn cpu_part(&mut self, part: Part) {
        let ms = self.part_start.elapsed().as_secs_f64() * 1e3;
        if part == Part::Shadow {
            self.cpu_shadow_ms += ms;
        }
        self.part_start = Instant::now();
    }

    /// Ends a part: on the wall clock, submits and waits.
    pub fn end_part(&mut self, gpu: &Gpu, part: Part) -> Result<(), RenderError> {
        if self.gpu_timed {
            return Ok(());
        }
        let encoder = std::mem::replace(
            &mut self.encoder,
            gpu.device.create_command_encoder(&Default::default()),
        );
        gpu.queue.submit([encoder.finish()]);
        gpu.wait()?;
        let ms = self.part_start.elapsed().as_secs_f64() * 1e3;
        match part {
            Part::Shadow => self.wall.0 += ms,
            Part::Main => self.wall.1 += ms,
        }
        self.part_start = Instant::now();
        Ok(())
    }

    /// Submits what is left, waits, and gives the part times.
    pub fn finish(mut self, gpu: &Gpu, timer: &Option<Timer>) -> Result<Timings, RenderError> {
        if let (true, Some(timer)) = (self.gpu_timed, timer) {
            timer.resolve(&mut self.encoder);
        }
        gpu.queue.submit([self.encoder.finish()]);
        gpu.wait()?;
        let (shadow, main, source) = match (self.gpu_timed, timer) {
            (true, Some(timer)) => {
                let (s, m) = timer.read(gpu)?;
                (s, m, TimingSource::GpuTimestamps)
            }
            _ => (self.wall.0, self.wall.1, TimingSource::WallClock),
        };
        Ok(Timings {
            shadow_pass_ms: shadow + self.cpu_shadow_ms,
            main_pass_ms: main,
            readback_ms: 0.0,
            source,
        })
    }
}
