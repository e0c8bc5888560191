//! SPIR-V embedded at build time (see `build.rs` and `glsl/variants.txt`).

use ash::vk;

use super::context::Context;
use super::error::GpuError;
use crate::Result;

mod generated {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}

/// The SPIR-V words of the embedded shader `name` (e.g. `"core_test.vert"`).
pub fn get(name: &str) -> Option<&'static [u32]> {
    generated::SHADERS
        .binary_search_by(|(n, _)| (*n).cmp(name))
        .ok()
        .map(|i| generated::SHADERS[i].1)
}

/// Names of every embedded shader, sorted.
pub fn names() -> impl Iterator<Item = &'static str> {
    generated::SHADERS.iter().map(|(n, _)| *n)
}

/// Like [`get`], with a typed error listing the embedded shaders.
pub fn require(name: &str) -> Result<&'static [u32]> {
    get(name).ok_or_else(|| {
        GpuError::UnknownShader {
            name: name.to_owned(),
            available: names().collect::<Vec<_>>().join(", "),
        }
        .into()
    })
}

/// The pipeline stage implied by a shader name's extension.
pub fn stage_of(name: &str) -> Option<vk::ShaderStageFlags> {
    let ext = name.rsplit('.').next()?;
    Some(match ext {
        "vert" => vk::ShaderStageFlags::VERTEX,
        "tesc" => vk::ShaderStageFlags::TESSELLATION_CONTROL,
        "tese" => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        "frag" => vk::ShaderStageFlags::FRAGMENT,
        "comp" => vk::ShaderStageFlags::COMPUTE,
        _ => return None,
    })
}

impl Context {
    /// Creates a shader module from the embedded shader `name`. The caller destroys it.
    pub fn shader_module(&self, name: &str) -> Result<vk::ShaderModule> {
        let code = require(name)?;
        let ci = vk::ShaderModuleCreateInfo::default().code(code);
        // SAFETY: code is SPIR-V produced by glslang at build time.
        let m = unsafe { self.device().create_shader_module(&ci, None) }
            .map_err(GpuError::vk("vkCreateShaderModule"))?;
        self.set_name(m, name);
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_table_is_sorted_and_valid_spirv() {
        let names: Vec<_> = names().collect();
        assert!(names.windows(2).all(|w| w[0] < w[1]), "{names:?}");
        for n in names {
            let w = get(n).expect("listed shader must be found");
            assert_eq!(w[0], 0x0723_0203, "{n} lacks the SPIR-V magic number");
            assert!(stage_of(n).is_some(), "{n} has no stage extension");
        }
    }

    #[test]
    fn variant_differs_from_base() {
        let a = get("core_test.frag").expect("core_test.frag");
        let b = get("core_test_invert.frag").expect("core_test_invert.frag");
        assert_ne!(a, b);
        assert!(require("no_such_shader.frag").is_err());
    }
}
