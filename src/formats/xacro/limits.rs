//! Resource limits of an expansion (values in `crate::tolerances`), so that a
//! macro bomb, a recursive macro, a long property chain or an expression that
//! builds a huge value is refused quickly with the place it grew:
//!
//! - [`Budget`]: the expander's counts: output elements and bytes, and the
//!   depths of its recursions, each in its own unit (macro calls, includes,
//!   nested elements, lazy properties evaluated inside one another);
//! - [`Meter`]: the work of evaluation, shared by every operation: steps (an
//!   expression node, an element, an item copied, compared or printed, 16
//!   bytes of text scanned), bytes of values created (cumulative, so live
//!   memory stays below it) and the size of each string and list. Once a
//!   limit trips the meter stays tripped, so an error cannot be swallowed and
//!   evaluation go on.
//!
//! The limit on time is the step budget, a count of work: the same file gives
//! the same answer on an idle laptop and on a loaded CI runner (a wall-clock
//! limit turned a good file into an error under load, issue 27). Behind it,
//! against an operation the meter does not charge, stands a backstop in CPU
//! time of the expanding thread (not wall time), [`XACRO_MAX_CPU_SECONDS`].

use super::tree::{err_at, Src};
use crate::diagnostic::{Error, Result};
use crate::tolerances::{
    XACRO_MAX_CPU_SECONDS, XACRO_MAX_ELEMENTS, XACRO_MAX_ELEMENT_DEPTH, XACRO_MAX_EVAL_BYTES,
    XACRO_MAX_INCLUDE_DEPTH, XACRO_MAX_LIST_ITEMS, XACRO_MAX_MACRO_DEPTH, XACRO_MAX_OUTPUT_BYTES,
    XACRO_MAX_PROPERTY_DEPTH, XACRO_MAX_STEPS, XACRO_MAX_STRING_BYTES,
};

/// The bytes one item of a list, tuple or dict is charged: the size of a
/// `value::Value` (asserted there at compile time, so a change of `Value`
/// that would make the charge wrong fails the build).
pub const VALUE_BYTES: u64 = 24;

/// The work of evaluation: steps, bytes created. See the module doc.
#[derive(Debug)]
pub struct Meter {
    steps: u64,
    bytes: u64,
    /// CPU time of this thread when the meter was made (s), for the backstop.
    started_cpu: f64,
    max_steps: u64,
    /// The limit that tripped (its message), sticky.
    tripped: Option<String>,
}

impl Default for Meter {
    fn default() -> Self {
        Meter::new()
    }
}

impl Meter {
    /// A meter with the limits of `crate::tolerances`.
    pub fn new() -> Self {
        Meter {
            steps: 0,
            bytes: 0,
            started_cpu: thread_cpu_seconds(),
            max_steps: XACRO_MAX_STEPS,
            tripped: None,
        }
    }

    /// A meter with a smaller step budget (bounded printing for messages).
    pub fn with_steps(max_steps: u64) -> Self {
        Meter {
            max_steps,
            ..Meter::new()
        }
    }

    /// The message of the limit that tripped, if one did.
    pub fn tripped(&self) -> Option<&str> {
        self.tripped.as_deref()
    }

    fn trip(&mut self, msg: String) -> String {
        self.tripped.get_or_insert(msg).clone()
    }

    /// `n` units of work (see the module doc); the CPU-time backstop is
    /// checked every 4096 units.
    pub fn work(&mut self, n: u64) -> std::result::Result<(), String> {
        if let Some(t) = &self.tripped {
            return Err(t.clone());
        }
        let before = self.steps;
        self.steps = self.steps.saturating_add(n);
        if self.steps > self.max_steps {
            return Err(self.trip(format!(
                "xacro evaluation took more than {} steps: stopped (real descriptions take a few thousand)",
                self.max_steps
            )));
        }
        if before >> 12 != self.steps >> 12
            && thread_cpu_seconds() - self.started_cpu > XACRO_MAX_CPU_SECONDS
        {
            return Err(self.trip(format!(
                "xacro expansion took more than {XACRO_MAX_CPU_SECONDS} s of CPU time: stopped"
            )));
        }
        Ok(())
    }

    /// One step.
    pub fn step(&mut self) -> std::result::Result<(), String> {
        self.work(1)
    }

    /// Scanning `bytes` of text.
    pub fn scan(&mut self, bytes: usize) -> std::result::Result<(), String> {
        self.work(1 + bytes as u64 / 16)
    }

    /// A string of `len` bytes is about to be created.
    pub fn string(&mut self, len: usize) -> std::result::Result<(), String> {
        if len > XACRO_MAX_STRING_BYTES {
            return Err(self.trip(format!(
                "a string of {len} bytes: above the {XACRO_MAX_STRING_BYTES}-byte cap on one value"
            )));
        }
        self.alloc(len as u64)?;
        self.scan(len)
    }

    /// A list (or tuple, dict) of `len` items is about to be created.
    pub fn list(&mut self, len: usize) -> std::result::Result<(), String> {
        if len > XACRO_MAX_LIST_ITEMS {
            return Err(self.trip(format!(
                "a list of {len} items: above the {XACRO_MAX_LIST_ITEMS}-item cap on one value"
            )));
        }
        self.alloc((len as u64).saturating_mul(VALUE_BYTES))?;
        self.work(1 + len as u64)
    }

    fn alloc(&mut self, bytes: u64) -> std::result::Result<(), String> {
        self.bytes = self.bytes.saturating_add(bytes);
        if self.bytes > XACRO_MAX_EVAL_BYTES {
            return Err(self.trip(format!(
                "xacro evaluation created more than {XACRO_MAX_EVAL_BYTES} bytes of values: stopped"
            )));
        }
        Ok(())
    }
}

/// CPU time (s) the calling thread has used: a budget in it does not shrink
/// when other processes load the machine. 0 where the platform has no such
/// clock (the step budget still holds there).
pub(crate) fn thread_cpu_seconds() -> f64 {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable timespec; the call only writes it.
        if unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) } == 0 {
            return ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9;
        }
    }
    0.0
}

pub struct Budget {
    elements: usize,
    bytes: usize,
    macro_depth: usize,
    pub include_depth: usize,
    element_depth: usize,
    property_depth: usize,
    /// The work of evaluation (every operation charges it).
    pub meter: Meter,
}

fn limit(src: &Src, msg: String, stack: &[String]) -> Error {
    let e = err_at(src, msg, stack);
    Error::limit(e.message).at(&e.location)
}

impl Budget {
    pub fn new() -> Self {
        Budget {
            elements: 0,
            bytes: 0,
            macro_depth: 0,
            include_depth: 0,
            element_depth: 0,
            property_depth: 0,
            meter: Meter::new(),
        }
    }

    /// One output element.
    pub fn element(&mut self, src: &Src, stack: &[String]) -> Result<()> {
        self.elements += 1;
        if self.elements > XACRO_MAX_ELEMENTS {
            return Err(limit(
                src,
                format!("xacro expansion produced more than {XACRO_MAX_ELEMENTS} elements: a macro bomb? (no robot description is that large)"),
                stack,
            ));
        }
        Ok(())
    }

    /// Output text.
    pub fn bytes(&mut self, n: usize, src: &Src, stack: &[String]) -> Result<()> {
        self.bytes = self.bytes.saturating_add(n);
        if self.bytes > XACRO_MAX_OUTPUT_BYTES {
            return Err(limit(
                src,
                format!("xacro expansion produced more than {XACRO_MAX_OUTPUT_BYTES} bytes: a macro bomb?"),
                stack,
            ));
        }
        Ok(())
    }

    /// Any step of the expander (an element met): the meter's step and time.
    pub fn tick(&mut self, src: &Src, stack: &[String]) -> Result<()> {
        self.meter.step().map_err(|m| limit(src, m, stack))
    }

    pub fn enter_macro(&mut self, name: &str, src: &Src, stack: &[String]) -> Result<()> {
        self.macro_depth += 1;
        if self.macro_depth > XACRO_MAX_MACRO_DEPTH {
            return Err(limit(
                src,
                format!("macro {name}: macro calls nested deeper than {XACRO_MAX_MACRO_DEPTH}: a recursive macro without an end?"),
                stack,
            ));
        }
        Ok(())
    }

    pub fn leave_macro(&mut self) {
        self.macro_depth = self.macro_depth.saturating_sub(1);
    }

    pub fn enter_include(&mut self, file: &str, src: &Src, stack: &[String]) -> Result<()> {
        self.include_depth += 1;
        if self.include_depth > XACRO_MAX_INCLUDE_DEPTH {
            return Err(limit(
                src,
                format!("including {file}: includes nested deeper than {XACRO_MAX_INCLUDE_DEPTH}: a file that includes itself?"),
                stack,
            ));
        }
        Ok(())
    }

    /// One level of element nesting in the expansion (an element inside an
    /// element, a macro body, a block, an `xacro:if`); [`Self::leave_element`]
    /// undoes it.
    pub fn enter_element(&mut self, src: &Src, stack: &[String]) -> Result<()> {
        self.element_depth += 1;
        if self.element_depth > XACRO_MAX_ELEMENT_DEPTH {
            return Err(limit(
                src,
                format!("elements nested deeper than {XACRO_MAX_ELEMENT_DEPTH} levels (macro bodies and xacro:if included): a URDF nests fewer than 10"),
                stack,
            ));
        }
        Ok(())
    }

    pub fn leave_element(&mut self) {
        self.element_depth = self.element_depth.saturating_sub(1);
    }

    /// One lazy property evaluated inside another (`a` defined as `${b}`, `b`
    /// as `${c}`, ...); [`Self::leave_property`] undoes it.
    pub fn enter_property(&mut self, name: &str, src: &Src, stack: &[String]) -> Result<()> {
        self.property_depth += 1;
        if self.property_depth > XACRO_MAX_PROPERTY_DEPTH {
            return Err(limit(
                src,
                format!("property {name}: properties defined through each other more than {XACRO_MAX_PROPERTY_DEPTH} deep (a chain of ${{...}} references)"),
                stack,
            ));
        }
        Ok(())
    }

    pub fn leave_property(&mut self) {
        self.property_depth = self.property_depth.saturating_sub(1);
    }
}
