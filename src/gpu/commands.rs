//! One-shot command submission with a bounded fence wait.

use ash::vk;

use super::context::Context;
use super::error::GpuError;
use crate::Result;

impl Context {
    /// Records commands with `record` into a fresh primary command buffer, submits it to the
    /// graphics queue and waits for completion. Waiting longer than the context's timeout
    /// returns [`GpuError::Timeout`] instead of hanging; the work keeps running, and every GPU
    /// object (buffer, image, render target, descriptor or query pool) dropped meanwhile first
    /// waits for it to finish, so dropping after a timeout is safe. Its command buffer and fence
    /// are released once it finishes (at the next submission or when the context drops).
    pub fn submit_once<R>(
        &self,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer) -> Result<R>,
    ) -> Result<R> {
        let s = &self.shared;
        let dev = &s.device;
        let pool = s.command_pool.lock().unwrap_or_else(|p| p.into_inner());
        self.release_finished(*pool);
        let ai = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: pool is valid and externally synchronised by the mutex.
        let cmd = unsafe { dev.allocate_command_buffers(&ai) }
            .map_err(GpuError::vk("vkAllocateCommandBuffers"))?[0];
        let free = |pool: vk::CommandPool| unsafe { dev.free_command_buffers(pool, &[cmd]) };
        let bi = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: freshly allocated command buffer.
        if let Err(e) = unsafe { dev.begin_command_buffer(cmd, &bi) } {
            free(*pool);
            return Err(GpuError::vk("vkBeginCommandBuffer")(e));
        }
        let out = match record(dev, cmd) {
            Ok(o) => o,
            Err(e) => {
                // SAFETY: end recording before freeing; errors here are irrelevant.
                unsafe {
                    let _ = dev.end_command_buffer(cmd);
                }
                free(*pool);
                return Err(e);
            }
        };
        // SAFETY: recording state.
        if let Err(e) = unsafe { dev.end_command_buffer(cmd) } {
            free(*pool);
            return Err(GpuError::vk("vkEndCommandBuffer")(e));
        }
        // SAFETY: valid device.
        let fence = match unsafe { dev.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(f) => f,
            Err(e) => {
                free(*pool);
                return Err(GpuError::vk("vkCreateFence")(e));
            }
        };
        let cmds = [cmd];
        let submit = vk::SubmitInfo::default().command_buffers(&cmds);
        let submitted = {
            let queue = s.queue.lock().unwrap_or_else(|p| p.into_inner());
            // SAFETY: queue access serialised by the mutex; fence unsignalled.
            unsafe { dev.queue_submit(*queue, &[submit], fence) }
        };
        if let Err(e) = submitted {
            unsafe { dev.destroy_fence(fence, None) };
            free(*pool);
            return Err(GpuError::vk("vkQueueSubmit")(e));
        }
        let timeout_ns = s.timeout_ms.saturating_mul(1_000_000);
        // SAFETY: fence belongs to this device.
        match unsafe { dev.wait_for_fences(&[fence], true, timeout_ns) } {
            Ok(()) => {
                unsafe { dev.destroy_fence(fence, None) };
                free(*pool);
                Ok(out)
            }
            Err(vk::Result::TIMEOUT) => {
                s.pending
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push((fence, cmd));
                Err(GpuError::Timeout(s.timeout_ms).into())
            }
            Err(e) => Err(GpuError::vk("vkWaitForFences")(e)),
        }
    }

    /// Frees command buffers and fences of timed-out submissions that have since finished.
    fn release_finished(&self, pool: vk::CommandPool) {
        let dev = &self.shared.device;
        let mut pending = self
            .shared
            .pending
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        pending.retain(|(fence, cmd)| {
            // SAFETY: fence and command buffer belong to this device / pool (locked by caller).
            let done = unsafe { dev.get_fence_status(*fence) }.unwrap_or(false);
            if done {
                unsafe {
                    dev.destroy_fence(*fence, None);
                    dev.free_command_buffers(pool, &[*cmd]);
                }
            }
            !done
        });
    }
}

/// Records a global memory barrier making `src` = (stage, access) writes visible to `dst` =
/// (stage, access). `cmd` must be recording, outside a render pass.
pub fn memory_barrier(
    dev: &ash::Device,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags, vk::AccessFlags),
    dst: (vk::PipelineStageFlags, vk::AccessFlags),
) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(src.1)
        .dst_access_mask(dst.1);
    // SAFETY: the caller records into a valid command buffer outside a render pass.
    unsafe {
        dev.cmd_pipeline_barrier(
            cmd,
            src.0,
            dst.0,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        );
    }
}

/// The barrier between a draw whose tessellation evaluation shader wrote a storage buffer (TES
/// capture) and the host reading that buffer.
pub fn tes_writes_to_host(dev: &ash::Device, cmd: vk::CommandBuffer) {
    memory_barrier(
        dev,
        cmd,
        (
            vk::PipelineStageFlags::TESSELLATION_EVALUATION_SHADER,
            vk::AccessFlags::SHADER_WRITE,
        ),
        (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
    );
}

/// The barrier between a draw whose geometry shader wrote a storage buffer (triangle capture;
/// needs `geometryShader`) and the host reading that buffer.
pub fn geometry_writes_to_host(dev: &ash::Device, cmd: vk::CommandBuffer) {
    memory_barrier(
        dev,
        cmd,
        (
            vk::PipelineStageFlags::GEOMETRY_SHADER,
            vk::AccessFlags::SHADER_WRITE,
        ),
        (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
    );
}
