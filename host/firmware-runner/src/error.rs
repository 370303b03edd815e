//! Why a co-simulation could not run or did not agree: the error type every co-simulation
//! step returns and the first firmware/model difference it carries. A leaf module, so the
//! QEMU runner and the trace reader can return it without importing their parent.

/// Why a co-simulation could not run or did not agree.
#[derive(Debug, thiserror::Error)]
pub enum CosimError {
    /// A required tool is missing.
    #[error("{0}: run `cargo xtask setup` to install qemu-system-arm and the thumb targets")]
    ToolMissing(String),
    /// Building the firmware failed.
    #[error("firmware build failed: {0}")]
    Build(String),
    /// QEMU failed.
    #[error("QEMU: {0}")]
    Qemu(String),
    /// The firmware rejected its input.
    #[error("the firmware rejected its input: {0}")]
    Firmware(String),
    /// The output trace is malformed.
    #[error("output trace, byte {offset}: {why}")]
    Trace {
        /// Byte offset in the trace file.
        offset: usize,
        /// What is wrong.
        why: String,
    },
    /// A file could not be written or read.
    #[error("{0}")]
    Io(String),
    /// Firmware and model disagree.
    #[error("{0}")]
    Mismatch(Box<Mismatch>),
}

/// The first difference between the firmware and the golden model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mismatch {
    /// Case index in the batch.
    pub case: usize,
    /// The case's name (seed, fault…).
    pub name: String,
    /// Event index within the case's measurement (or, for a `force.` signal, force) events
    /// (`None`: the trace's shape differs).
    pub event: Option<usize>,
    /// The event's time, ticks.
    pub time: u64,
    /// The signal (a `MeasureOutputs` field, or a trace property).
    pub signal: String,
    /// The golden model's value.
    pub model: String,
    /// The firmware's value.
    pub firmware: String,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let at = match self.event {
            Some(i) => format!("event {i} (time {} ticks)", self.time),
            None => "trace".to_string(),
        };
        write!(
            f,
            "firmware differs from the golden model in case {} ({}), {at}: signal `{}`: model {}, firmware {}",
            self.case, self.name, self.signal, self.model, self.firmware
        )
    }
}
