//! Physical-device description, feature checks and selection (`TESSERA_DEVICE`).

use ash::vk;

use super::error::{DeviceReport, GpuError};

/// Optional device features tessera uses. Only `TessellationShader` is needed to pick a device;
/// the others are enabled when present and checked with [`super::Context::require`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Feature {
    /// `tessellationShader`.
    TessellationShader,
    /// `fillModeNonSolid` (wireframe).
    FillModeNonSolid,
    /// `pipelineStatisticsQuery`.
    PipelineStatisticsQuery,
    /// `vertexPipelineStoresAndAtomics` (SSBO writes from TCS/TES).
    VertexPipelineStoresAndAtomics,
    /// `geometryShader` (the triangle capture of `render::static_draw`).
    GeometryShader,
    /// `timestampComputeAndGraphics` and non-zero timestamp bits on the graphics queue.
    Timestamps,
    /// `shaderFloat64`.
    ShaderFloat64,
    /// `dynamicRendering` (Vulkan 1.3 / VK_KHR_dynamic_rendering): drawing without a render pass.
    DynamicRendering,
}

impl Feature {
    /// The Vulkan name of the feature.
    pub fn name(self) -> &'static str {
        match self {
            Feature::TessellationShader => "tessellationShader",
            Feature::FillModeNonSolid => "fillModeNonSolid",
            Feature::PipelineStatisticsQuery => "pipelineStatisticsQuery",
            Feature::VertexPipelineStoresAndAtomics => "vertexPipelineStoresAndAtomics",
            Feature::GeometryShader => "geometryShader",
            Feature::Timestamps => "timestampComputeAndGraphics",
            Feature::ShaderFloat64 => "shaderFloat64",
            Feature::DynamicRendering => "dynamicRendering",
        }
    }
}

/// Which optional features the device has (and the context enabled).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DeviceFeatures {
    /// `tessellationShader`.
    pub tessellation_shader: bool,
    /// `fillModeNonSolid`.
    pub fill_mode_non_solid: bool,
    /// `pipelineStatisticsQuery`.
    pub pipeline_statistics_query: bool,
    /// `vertexPipelineStoresAndAtomics`.
    pub vertex_pipeline_stores_and_atomics: bool,
    /// `geometryShader`.
    pub geometry_shader: bool,
    /// Timestamps usable on the graphics queue.
    pub timestamps: bool,
    /// `shaderFloat64`.
    pub shader_float64: bool,
    /// `dynamicRendering` (Vulkan 1.3 core feature).
    pub dynamic_rendering: bool,
}

impl DeviceFeatures {
    /// Whether `f` is available.
    pub fn has(&self, f: Feature) -> bool {
        match f {
            Feature::TessellationShader => self.tessellation_shader,
            Feature::FillModeNonSolid => self.fill_mode_non_solid,
            Feature::PipelineStatisticsQuery => self.pipeline_statistics_query,
            Feature::VertexPipelineStoresAndAtomics => self.vertex_pipeline_stores_and_atomics,
            Feature::GeometryShader => self.geometry_shader,
            Feature::Timestamps => self.timestamps,
            Feature::ShaderFloat64 => self.shader_float64,
            Feature::DynamicRendering => self.dynamic_rendering,
        }
    }

    /// Names of the features of `wanted` that are absent.
    pub fn missing(&self, wanted: &[Feature]) -> Vec<String> {
        wanted
            .iter()
            .filter(|f| !self.has(**f))
            .map(|f| f.name().to_owned())
            .collect()
    }
}

/// Device limits tessera honours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceLimits {
    /// `maxTessellationPatchSize` (control points per patch).
    pub max_tessellation_patch_size: u32,
    /// `maxTessellationGenerationLevel` (largest tessellation level).
    pub max_tessellation_generation_level: u32,
    /// `maxTessellationControlPerVertexOutputComponents`.
    pub max_tess_control_per_vertex_output_components: u32,
    /// `maxTessellationControlPerPatchOutputComponents`.
    pub max_tess_control_per_patch_output_components: u32,
    /// `maxTessellationControlTotalOutputComponents`.
    pub max_tess_control_total_output_components: u32,
    /// `maxTessellationEvaluationInputComponents`.
    pub max_tess_evaluation_input_components: u32,
    /// `maxTessellationEvaluationOutputComponents`.
    pub max_tess_evaluation_output_components: u32,
    /// Nanoseconds per timestamp tick (`timestampPeriod`).
    pub timestamp_period_ns: f32,
    /// `timestampValidBits` of the graphics queue family (0 = no timestamps).
    pub timestamp_valid_bits: u32,
    /// `framebufferColorSampleCounts & framebufferDepthSampleCounts`.
    pub sample_counts: vk::SampleCountFlags,
    /// `maxImageDimension2D`.
    pub max_image_dimension_2d: u32,
    /// `maxPushConstantsSize` in bytes.
    pub max_push_constants_size: u32,
    /// `maxStorageBufferRange` in bytes.
    pub max_storage_buffer_range: u32,
    /// `maxBoundDescriptorSets`.
    pub max_bound_descriptor_sets: u32,
    /// `maxPerStageDescriptorStorageBuffers`.
    pub max_per_stage_storage_buffers: u32,
    /// `minStorageBufferOffsetAlignment`.
    pub min_storage_buffer_offset_alignment: u64,
    /// `minUniformBufferOffsetAlignment`.
    pub min_uniform_buffer_offset_alignment: u64,
}

impl DeviceLimits {
    /// Whether `samples` (1, 2, 4, ...) is a supported colour+depth sample count.
    pub fn supports_samples(&self, samples: u32) -> bool {
        samples.is_power_of_two()
            && samples <= 64
            && self
                .sample_counts
                .contains(vk::SampleCountFlags::from_raw(samples))
    }

    /// Every supported sample count, ascending.
    pub fn supported_sample_counts(&self) -> Vec<u32> {
        (0..7)
            .map(|k| 1u32 << k)
            .filter(|s| self.supports_samples(*s))
            .collect()
    }
}

/// Everything known about the selected device.
#[derive(Debug, Clone)]
pub struct DeviceInfo {
    /// `deviceName`.
    pub name: String,
    /// Device type as text.
    pub kind: String,
    /// Vulkan API version of the device (major, minor, patch).
    pub api_version: (u32, u32, u32),
    /// Available (and enabled) optional features.
    pub features: DeviceFeatures,
    /// Limits.
    pub limits: DeviceLimits,
    /// Index of the graphics queue family used.
    pub queue_family: u32,
}

impl std::fmt::Display for DeviceInfo {
    /// One line: name, type, API version, tessellation limits, timestamp resolution.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (a, b, c) = self.api_version;
        let l = &self.limits;
        write!(
            f,
            "{} ({}, Vulkan {a}.{b}.{c}; max tess level {}, max patch size {}, samples {:?}, \
             timestamp period {} ns / {} bits)",
            self.name,
            self.kind,
            l.max_tessellation_generation_level,
            l.max_tessellation_patch_size,
            l.supported_sample_counts(),
            l.timestamp_period_ns,
            l.timestamp_valid_bits
        )
    }
}

/// One enumerated device before selection.
#[derive(Debug, Clone)]
pub(crate) struct Candidate {
    pub handle: vk::PhysicalDevice,
    pub info: DeviceInfo,
    /// False when the device has no graphics queue.
    pub has_graphics_queue: bool,
}

impl Candidate {
    /// The device's report, with what it lacks among `required`.
    pub fn report(&self, required: &[Feature]) -> DeviceReport {
        let mut missing = self.info.features.missing(required);
        if !self.has_graphics_queue {
            missing.push("a graphics queue".to_owned());
        }
        let (a, b, c) = self.info.api_version;
        DeviceReport {
            name: self.info.name.clone(),
            kind: self.info.kind.clone(),
            api_version: format!("{a}.{b}.{c}"),
            missing,
        }
    }
}

/// Picks a device: the first whose name contains `wanted` (case-insensitive) if given, else the
/// first that has every `required` feature and a graphics queue.
pub(crate) fn select(
    candidates: &[Candidate],
    wanted: Option<&str>,
    required: &[Feature],
) -> Result<usize, GpuError> {
    let reports: Vec<DeviceReport> = candidates.iter().map(|c| c.report(required)).collect();
    match wanted.map(str::trim).filter(|w| !w.is_empty()) {
        Some(w) => {
            let lw = w.to_lowercase();
            let Some(i) = reports
                .iter()
                .position(|r| r.name.to_lowercase().contains(&lw))
            else {
                return Err(GpuError::DeviceNotFound {
                    wanted: w.to_owned(),
                    devices: reports,
                });
            };
            if reports[i].missing.is_empty() {
                Ok(i)
            } else {
                Err(GpuError::MissingFeatures {
                    name: reports[i].name.clone(),
                    missing: reports[i].missing.clone(),
                    devices: reports,
                })
            }
        }
        None => reports
            .iter()
            .position(|r| r.missing.is_empty())
            .ok_or(GpuError::NoSuitableDevice { devices: reports }),
    }
}

/// Reads the features and limits of `pd`.
pub(crate) fn describe(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Candidate {
    // SAFETY: `pd` was enumerated from `instance`.
    let (props, feats, families) = unsafe {
        (
            instance.get_physical_device_properties(pd),
            instance.get_physical_device_features(pd),
            instance.get_physical_device_queue_family_properties(pd),
        )
    };
    let dynamic_rendering = props.api_version >= vk::API_VERSION_1_3 && {
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
        // SAFETY: a Vulkan 1.3 device (instances are created for API 1.2 or newer).
        unsafe { instance.get_physical_device_features2(pd, &mut f2) };
        f13.dynamic_rendering == vk::TRUE
    };
    let graphics = families
        .iter()
        .position(|q| q.queue_flags.contains(vk::QueueFlags::GRAPHICS) && q.queue_count > 0);
    let queue_family = graphics.unwrap_or(0) as u32;
    let ts_bits = graphics.map_or(0, |g| families[g].timestamp_valid_bits);
    let l = &props.limits;
    let name = props
        .device_name_as_c_str()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|_| "(unnamed device)".to_owned());
    let kind = match props.device_type {
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
        vk::PhysicalDeviceType::CPU => "CPU",
        _ => "other",
    }
    .to_owned();
    let v = props.api_version;
    Candidate {
        handle: pd,
        has_graphics_queue: graphics.is_some(),
        info: DeviceInfo {
            name,
            kind,
            api_version: (
                vk::api_version_major(v),
                vk::api_version_minor(v),
                vk::api_version_patch(v),
            ),
            features: DeviceFeatures {
                tessellation_shader: feats.tessellation_shader == vk::TRUE,
                fill_mode_non_solid: feats.fill_mode_non_solid == vk::TRUE,
                pipeline_statistics_query: feats.pipeline_statistics_query == vk::TRUE,
                vertex_pipeline_stores_and_atomics: feats.vertex_pipeline_stores_and_atomics
                    == vk::TRUE,
                geometry_shader: feats.geometry_shader == vk::TRUE,
                timestamps: l.timestamp_compute_and_graphics == vk::TRUE && ts_bits > 0,
                shader_float64: feats.shader_float64 == vk::TRUE,
                dynamic_rendering,
            },
            limits: DeviceLimits {
                max_tessellation_patch_size: l.max_tessellation_patch_size,
                max_tessellation_generation_level: l.max_tessellation_generation_level,
                max_tess_control_per_vertex_output_components: l
                    .max_tessellation_control_per_vertex_output_components,
                max_tess_control_per_patch_output_components: l
                    .max_tessellation_control_per_patch_output_components,
                max_tess_control_total_output_components: l
                    .max_tessellation_control_total_output_components,
                max_tess_evaluation_input_components: l
                    .max_tessellation_evaluation_input_components,
                max_tess_evaluation_output_components: l
                    .max_tessellation_evaluation_output_components,
                timestamp_period_ns: l.timestamp_period,
                timestamp_valid_bits: ts_bits,
                sample_counts: l.framebuffer_color_sample_counts
                    & l.framebuffer_depth_sample_counts,
                max_image_dimension_2d: l.max_image_dimension2_d,
                max_push_constants_size: l.max_push_constants_size,
                max_storage_buffer_range: l.max_storage_buffer_range,
                max_bound_descriptor_sets: l.max_bound_descriptor_sets,
                max_per_stage_storage_buffers: l.max_per_stage_descriptor_storage_buffers,
                min_storage_buffer_offset_alignment: l.min_storage_buffer_offset_alignment,
                min_uniform_buffer_offset_alignment: l.min_uniform_buffer_offset_alignment,
            },
            queue_family,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cand(name: &str, tess: bool) -> Candidate {
        Candidate {
            handle: vk::PhysicalDevice::null(),
            has_graphics_queue: true,
            info: DeviceInfo {
                name: name.to_owned(),
                kind: "CPU".to_owned(),
                api_version: (1, 3, 0),
                features: DeviceFeatures {
                    tessellation_shader: tess,
                    ..DeviceFeatures::default()
                },
                limits: DeviceLimits {
                    max_tessellation_patch_size: 32,
                    max_tessellation_generation_level: 64,
                    max_tess_control_per_vertex_output_components: 128,
                    max_tess_control_per_patch_output_components: 128,
                    max_tess_control_total_output_components: 4096,
                    max_tess_evaluation_input_components: 128,
                    max_tess_evaluation_output_components: 128,
                    timestamp_period_ns: 1.0,
                    timestamp_valid_bits: 64,
                    sample_counts: vk::SampleCountFlags::TYPE_1 | vk::SampleCountFlags::TYPE_4,
                    max_image_dimension_2d: 4096,
                    max_push_constants_size: 128,
                    max_storage_buffer_range: 1 << 27,
                    max_bound_descriptor_sets: 8,
                    max_per_stage_storage_buffers: 16,
                    min_storage_buffer_offset_alignment: 16,
                    min_uniform_buffer_offset_alignment: 16,
                },
                queue_family: 0,
            },
        }
    }

    #[test]
    fn picks_first_with_tessellation() {
        let c = [cand("Old GPU", false), cand("llvmpipe", true)];
        assert_eq!(select(&c, None, &[Feature::TessellationShader]), Ok(1));
    }

    #[test]
    fn named_device_is_case_insensitive_substring() {
        let c = [cand("Alpha", true), cand("llvmpipe (LLVM 15)", true)];
        assert_eq!(
            select(&c, Some("LLVMPIPE"), &[Feature::TessellationShader]),
            Ok(1)
        );
    }

    #[test]
    fn missing_features_are_named() {
        let c = [cand("Old GPU", false)];
        let e = select(&c, None, &[Feature::TessellationShader]).unwrap_err();
        let GpuError::NoSuitableDevice { devices } = &e else {
            panic!("wrong error {e:?}")
        };
        assert_eq!(devices[0].missing, vec!["tessellationShader".to_owned()]);
        assert!(e.to_string().contains("Old GPU"));
        let e = select(&c, Some("old"), &[Feature::TessellationShader]).unwrap_err();
        assert!(matches!(e, GpuError::MissingFeatures { .. }), "{e:?}");
        assert!(e.to_string().contains("tessellationShader"));
    }

    #[test]
    fn unknown_name_lists_devices() {
        let c = [cand("Alpha", true), cand("Beta", true)];
        let e = select(&c, Some("gamma"), &[]).unwrap_err();
        let s = e.to_string();
        assert!(
            s.contains("Alpha") && s.contains("Beta") && s.contains("gamma"),
            "{s}"
        );
    }

    #[test]
    fn sample_counts() {
        let l = cand("x", true).info.limits;
        assert_eq!(l.supported_sample_counts(), vec![1, 4]);
        assert!(!l.supports_samples(3));
    }
}
