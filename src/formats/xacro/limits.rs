//! Resource limits of an expansion (values in `crate::tolerances`): output
//! elements and bytes, macro nesting, include nesting and wall time, so a
//! macro bomb or a recursive macro is refused quickly with the place it grew.

use super::tree::{err_at, Src};
use crate::diagnostic::{Error, Result};
use crate::tolerances::{
    XACRO_MAX_ELEMENTS, XACRO_MAX_INCLUDE_DEPTH, XACRO_MAX_MACRO_DEPTH, XACRO_MAX_OUTPUT_BYTES,
    XACRO_MAX_SECONDS,
};
use std::time::Instant;

pub struct Budget {
    elements: usize,
    bytes: usize,
    macro_depth: usize,
    pub include_depth: usize,
    ticks: u64,
    started: Instant,
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
            ticks: 0,
            started: Instant::now(),
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

    /// Any step: the wall-time check (every 1024 steps).
    pub fn tick(&mut self, src: &Src, stack: &[String]) -> Result<()> {
        self.ticks += 1;
        if self.ticks.is_multiple_of(1024)
            && self.started.elapsed().as_secs_f64() > XACRO_MAX_SECONDS
        {
            return Err(limit(
                src,
                format!("xacro expansion took more than {XACRO_MAX_SECONDS} s: stopped"),
                stack,
            ));
        }
        Ok(())
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
}
