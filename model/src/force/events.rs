//! The force path's input events: what the ADC, the control timer and the CNC tell the
//! [`crate::force::kernel::ForceKernel`], one call each. Their wire kinds and canonical
//! same-time order are in [`crate::wire::force_event`].

use crate::force::sampling::AdcCodes;

/// One input event of the force path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ForceEvent {
    /// One ADC sample of every channel (1 kHz).
    Sample(AdcCodes),
    /// Control period tick (20 Hz): estimate, control, monitor wear.
    Tick,
    /// CNC: no-load identification on (clears its sums) / off (solves B and T_fco).
    Identify(bool),
    /// CNC: force control on (tool in cut; the controller restarts bumplessly from the
    /// current override) / off (override = `manual_override`).
    Control(bool),
    /// CNC: the cutting conditions changed to condition set `index` (wear monitor).
    Conditions(u8),
    /// CNC: a new tool was put in; clears the wear alarm.
    ToolChanged,
}
