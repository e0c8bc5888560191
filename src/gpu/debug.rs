//! Debug-utils messenger: counts validation errors / warnings, keeps the messages (what
//! [`super::Context::validation_messages`] returns) and forwards each one to the `log` crate
//! (`error` / `warn` level); the library never prints.

use std::ffi::{c_void, CStr};
use std::sync::Mutex;

use ash::vk;

/// At most this many messages are kept (the counters keep counting).
const MAX_KEPT: usize = 2000;

/// Validation messages collected by the messenger.
#[derive(Debug, Default, Clone)]
pub struct ValidationLog {
    /// Number of messages with ERROR severity.
    pub errors: usize,
    /// Number of messages with WARNING severity.
    pub warnings: usize,
    /// Kept messages (`"ERROR: ..."` / `"WARNING: ..."`), oldest first.
    pub messages: Vec<String>,
}

/// The messenger's user data. Boxed so its address is stable for the callback.
pub(crate) type SharedLog = Mutex<ValidationLog>;

/// Fills a messenger create-info pointing at `log`.
pub(crate) fn messenger_info(log: &SharedLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(callback))
        .user_data(log as *const SharedLog as *mut c_void)
}

unsafe extern "system" fn callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if user.is_null() || data.is_null() {
        return vk::FALSE;
    }
    // SAFETY: `user` points at the boxed `SharedLog` owned by the context, which outlives the
    // messenger and the instance; `data` is valid for the duration of the call.
    let (log, data) = unsafe { (&*(user as *const SharedLog), &*data) };
    let text = if data.p_message.is_null() {
        String::from("(no message)")
    } else {
        // SAFETY: the layer passes a NUL-terminated string.
        unsafe { CStr::from_ptr(data.p_message) }
            .to_string_lossy()
            .into_owned()
    };
    let is_error = severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR);
    let tag = if is_error { "ERROR" } else { "WARNING" };
    let kind = if types.contains(vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE) {
        " (performance)"
    } else {
        ""
    };
    let level = if is_error {
        log::Level::Error
    } else {
        log::Level::Warn
    };
    log::log!(level, "[vulkan {tag}{kind}] {text}");
    if let Ok(mut l) = log.lock() {
        if is_error {
            l.errors += 1;
        } else {
            l.warnings += 1;
        }
        if l.messages.len() < MAX_KEPT {
            l.messages.push(format!("{tag}{kind}: {text}"));
        }
    }
    vk::FALSE
}
