//! GPU timestamps and pipeline statistics.

use std::sync::Arc;

use ash::vk;

use super::context::{Context, Shared};
use super::device::Feature;
use super::error::{invalid, GpuError};
use crate::Result;

/// Per-pass GPU timer from timestamp queries (two timestamps per pass).
pub struct GpuTimer {
    shared: Arc<Shared>,
    pool: vk::QueryPool,
    capacity: u32,
    labels: Vec<String>,
    period_ns: f64,
    mask: u64,
}

impl GpuTimer {
    /// A timer for up to `passes` passes per recording. Needs [`Feature::Timestamps`].
    pub fn new(ctx: &Context, passes: u32) -> Result<GpuTimer> {
        ctx.require(&[Feature::Timestamps])?;
        if passes == 0 {
            return invalid("GpuTimer needs at least one pass");
        }
        let ci = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(passes * 2);
        // SAFETY: valid create info.
        let pool = unsafe { ctx.device().create_query_pool(&ci, None) }
            .map_err(GpuError::vk("vkCreateQueryPool"))?;
        ctx.set_name(pool, "timestamp queries");
        let lim = &ctx.info().limits;
        let bits = lim.timestamp_valid_bits.min(64);
        Ok(GpuTimer {
            shared: ctx.shared.clone(),
            pool,
            capacity: passes,
            labels: Vec::new(),
            period_ns: f64::from(lim.timestamp_period_ns),
            mask: if bits >= 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            },
        })
    }

    /// Resets all queries; record before any pass (outside a render pass).
    pub fn reset(&mut self, cmd: vk::CommandBuffer) {
        self.labels.clear();
        // SAFETY: cmd is recording outside a render pass.
        unsafe {
            self.shared
                .device
                .cmd_reset_query_pool(cmd, self.pool, 0, self.capacity * 2)
        };
    }

    /// Writes the start timestamp of a new pass named `label`; returns its index.
    pub fn begin(&mut self, cmd: vk::CommandBuffer, label: &str) -> Result<u32> {
        let i = self.labels.len() as u32;
        if i >= self.capacity {
            return invalid(format!("GpuTimer full ({} passes)", self.capacity));
        }
        self.labels.push(label.to_owned());
        // SAFETY: query 2i was reset by `reset`.
        unsafe {
            self.shared.device.cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                self.pool,
                2 * i,
            )
        };
        Ok(i)
    }

    /// Writes the end timestamp of pass `index`.
    pub fn end(&mut self, cmd: vk::CommandBuffer, index: u32) -> Result<()> {
        if index as usize >= self.labels.len() {
            return invalid(format!("GpuTimer::end of unknown pass {index}"));
        }
        // SAFETY: query 2i+1 was reset by `reset`.
        unsafe {
            self.shared.device.cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                self.pool,
                2 * index + 1,
            )
        };
        Ok(())
    }

    /// `(label, milliseconds)` per pass, after the submission finished. Tick differences are
    /// taken modulo 2^timestampValidBits and scaled by timestampPeriod.
    pub fn results(&self) -> Result<Vec<(String, f64)>> {
        let n = self.labels.len();
        if n == 0 {
            return Ok(Vec::new());
        }
        let mut ticks = vec![0u64; 2 * n];
        // SAFETY: queries 0..2n were written by a finished submission.
        unsafe {
            self.shared.device.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .map_err(GpuError::vk("vkGetQueryPoolResults"))?;
        Ok(self
            .labels
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let d = ticks_to_ms(ticks[2 * i], ticks[2 * i + 1], self.mask, self.period_ns);
                (l.clone(), d)
            })
            .collect())
    }
}

/// Elapsed milliseconds between two raw timestamps (wrap-around within the valid bits).
pub fn ticks_to_ms(start: u64, end: u64, mask: u64, period_ns: f64) -> f64 {
    let d = (end & mask).wrapping_sub(start & mask) & mask;
    d as f64 * period_ns * 1e-6
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        if !self.shared.wait_pending() {
            return;
        }
        // SAFETY: no pending work uses the pool.
        unsafe { self.shared.device.destroy_query_pool(self.pool, None) };
    }
}

/// Pipeline statistics of one query.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PipelineStats {
    /// Input-assembly vertices.
    pub input_vertices: u64,
    /// Input-assembly primitives (patches).
    pub input_primitives: u64,
    /// Vertex shader invocations.
    pub vertex_invocations: u64,
    /// Tessellation control shader patches.
    pub tcs_patches: u64,
    /// Tessellation evaluation shader invocations.
    pub tes_invocations: u64,
    /// Primitives that reached the clipping stage.
    pub clipping_invocations: u64,
    /// Primitives output by clipping.
    pub clipping_primitives: u64,
    /// Fragment shader invocations.
    pub fragment_invocations: u64,
}

const STAT_FLAGS: [vk::QueryPipelineStatisticFlags; 8] = [
    vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_VERTICES,
    vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::TESSELLATION_CONTROL_SHADER_PATCHES,
    vk::QueryPipelineStatisticFlags::TESSELLATION_EVALUATION_SHADER_INVOCATIONS,
];

/// One pipeline-statistics query (begin/end around draws).
pub struct StatsQuery {
    shared: Arc<Shared>,
    pool: vk::QueryPool,
}

impl StatsQuery {
    /// Creates the query. Needs [`Feature::PipelineStatisticsQuery`].
    pub fn new(ctx: &Context) -> Result<StatsQuery> {
        ctx.require(&[Feature::PipelineStatisticsQuery])?;
        let flags = STAT_FLAGS
            .iter()
            .fold(vk::QueryPipelineStatisticFlags::empty(), |a, f| a | *f);
        let ci = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(1)
            .pipeline_statistics(flags);
        // SAFETY: feature enabled, valid create info.
        let pool = unsafe { ctx.device().create_query_pool(&ci, None) }
            .map_err(GpuError::vk("vkCreateQueryPool"))?;
        ctx.set_name(pool, "pipeline statistics query");
        Ok(StatsQuery {
            shared: ctx.shared.clone(),
            pool,
        })
    }

    /// Resets the query; record outside a render pass before `begin`.
    pub fn reset(&self, cmd: vk::CommandBuffer) {
        // SAFETY: recording outside a render pass.
        unsafe {
            self.shared
                .device
                .cmd_reset_query_pool(cmd, self.pool, 0, 1)
        };
    }

    /// Starts counting (inside or outside a render pass; end in the same subpass).
    pub fn begin(&self, cmd: vk::CommandBuffer) {
        // SAFETY: query reset beforehand.
        unsafe {
            self.shared
                .device
                .cmd_begin_query(cmd, self.pool, 0, vk::QueryControlFlags::empty())
        };
    }

    /// Stops counting.
    pub fn end(&self, cmd: vk::CommandBuffer) {
        // SAFETY: query active.
        unsafe { self.shared.device.cmd_end_query(cmd, self.pool, 0) };
    }

    /// The counters, after the submission finished.
    pub fn results(&self) -> Result<PipelineStats> {
        // Results come in ascending bit order of the enabled flags.
        let mut order: Vec<_> = STAT_FLAGS.iter().map(|f| f.as_raw()).collect();
        order.sort_unstable();
        let mut raw = [0u64; 8];
        // SAFETY: the query was ended by a finished submission; one query of 8 u64 values.
        unsafe {
            self.shared.device.get_query_pool_results(
                self.pool,
                0,
                std::slice::from_mut(&mut raw),
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .map_err(GpuError::vk("vkGetQueryPoolResults"))?;
        let get = |f: vk::QueryPipelineStatisticFlags| {
            order
                .iter()
                .position(|b| *b == f.as_raw())
                .map_or(0, |i| raw[i])
        };
        use vk::QueryPipelineStatisticFlags as F;
        Ok(PipelineStats {
            input_vertices: get(F::INPUT_ASSEMBLY_VERTICES),
            input_primitives: get(F::INPUT_ASSEMBLY_PRIMITIVES),
            vertex_invocations: get(F::VERTEX_SHADER_INVOCATIONS),
            tcs_patches: get(F::TESSELLATION_CONTROL_SHADER_PATCHES),
            tes_invocations: get(F::TESSELLATION_EVALUATION_SHADER_INVOCATIONS),
            clipping_invocations: get(F::CLIPPING_INVOCATIONS),
            clipping_primitives: get(F::CLIPPING_PRIMITIVES),
            fragment_invocations: get(F::FRAGMENT_SHADER_INVOCATIONS),
        })
    }
}

impl Drop for StatsQuery {
    fn drop(&mut self) {
        if !self.shared.wait_pending() {
            return;
        }
        // SAFETY: no pending work uses the pool.
        unsafe { self.shared.device.destroy_query_pool(self.pool, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::ticks_to_ms;

    #[test]
    fn timestamp_wraps_within_valid_bits() {
        // 36 valid bits: end wrapped past 2^36.
        let mask = (1u64 << 36) - 1;
        let start = mask - 999; // 1000 ticks before wrap
        let end = 500; // 500 ticks after wrap
        let ms = ticks_to_ms(start, end, mask, 2.0);
        assert!((ms - 1500.0 * 2.0 * 1e-6).abs() < 1e-12, "{ms}");
        // Garbage above the valid bits is ignored.
        let ms = ticks_to_ms(start | (7 << 40), end | (3 << 50), mask, 1.0);
        assert!((ms - 1500.0 * 1e-6).abs() < 1e-12, "{ms}");
    }
}
