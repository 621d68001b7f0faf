//! Temporary files removed when the process is interrupted.
//!
//! A temporary file is removed by its owner's `Drop` on every path Rust runs:
//! a returned error, a panic that unwinds. A signal whose default action ends
//! the process runs no `Drop`, so while a temporary exists its path is
//! [`register`]ed here, and a handler for SIGINT, SIGTERM and SIGHUP (what a
//! terminal's Ctrl-C, a CI runner's cancel and a closed terminal send)
//! unlinks every registered path, then restores the default action and
//! re-raises the signal: the process still dies of it, with the same status.
//!
//! The handler is installed once, on the first registration, and only for a
//! signal whose action is still the default: a host that handles or ignores
//! one (a Python interpreter's SIGINT, `nohup`'s SIGHUP) keeps its own. It
//! does only async-signal-safe work: atomic loads, `unlink(2)`, `signal(2)`,
//! `raise(3)`. SIGKILL cannot be caught: a killed process may leave its
//! temporary (the target is never half-written). At most
//! [`MAX_SIGNAL_CLEANUP_PATHS`](crate::tolerances::MAX_SIGNAL_CLEANUP_PATHS) paths are
//! registered at once; a write beyond that runs unprotected against signals.

use std::path::Path;

use crate::tolerances::MAX_SIGNAL_CLEANUP_PATHS as SLOTS;

/// A registration: dropping it forgets the path (the owner removes or renames
/// the file itself).
pub struct Registered {
    #[cfg(unix)]
    slot: Option<usize>,
}

#[cfg(unix)]
mod imp {
    use super::SLOTS;
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    use std::path::Path;
    use std::ptr::null_mut;
    use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering::SeqCst};
    use std::sync::Once;

    static PATHS: [AtomicPtr<libc::c_char>; SLOTS] = [const { AtomicPtr::new(null_mut()) }; SLOTS];
    /// Set by the handler before it reads `PATHS`: a path swapped out after
    /// that is never freed (the handler may be reading it; the process is
    /// about to end anyway).
    static IN_HANDLER: AtomicBool = AtomicBool::new(false);
    static INSTALL: Once = Once::new();
    const SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

    extern "C" fn on_signal(sig: libc::c_int) {
        IN_HANDLER.store(true, SeqCst);
        for s in &PATHS {
            let p = s.load(SeqCst);
            if !p.is_null() {
                // SAFETY: `p` is a NUL-terminated string leaked by `register`
                // and never freed once IN_HANDLER is set.
                unsafe { libc::unlink(p) };
            }
        }
        // SAFETY: both are async-signal-safe; the signal is blocked while the
        // handler runs, so it is delivered with the default action on return.
        unsafe {
            libc::signal(sig, libc::SIG_DFL);
            libc::raise(sig);
        }
    }

    fn install() {
        INSTALL.call_once(|| {
            for sig in SIGNALS {
                // SAFETY: plain sigaction(2) calls on zeroed structs.
                unsafe {
                    let mut old: libc::sigaction = std::mem::zeroed();
                    if libc::sigaction(sig, std::ptr::null(), &mut old) != 0
                        || old.sa_sigaction != libc::SIG_DFL
                    {
                        continue;
                    }
                    let mut new: libc::sigaction = std::mem::zeroed();
                    new.sa_sigaction = on_signal as *const () as libc::sighandler_t;
                    libc::sigemptyset(&mut new.sa_mask);
                    libc::sigaction(sig, &new, null_mut());
                }
            }
        });
    }

    pub fn register(path: &Path) -> Option<usize> {
        install();
        let raw = CString::new(path.as_os_str().as_bytes()).ok()?.into_raw();
        for (i, s) in PATHS.iter().enumerate() {
            if s.compare_exchange(null_mut(), raw, SeqCst, SeqCst).is_ok() {
                return Some(i);
            }
        }
        // SAFETY: `raw` came from `into_raw` above and was never shared.
        drop(unsafe { CString::from_raw(raw) });
        None
    }

    pub fn forget(slot: usize) {
        let p = PATHS[slot].swap(null_mut(), SeqCst);
        if !p.is_null() && !IN_HANDLER.load(SeqCst) {
            // SAFETY: swapped out, so no later handler sees it, and no
            // handler has started reading.
            drop(unsafe { CString::from_raw(p) });
        }
    }
}

/// Remove `path` if the process is interrupted before the registration is
/// dropped (see the module documentation).
pub fn register(path: &Path) -> Registered {
    #[cfg(unix)]
    {
        Registered {
            slot: imp::register(path),
        }
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        Registered {}
    }
}

impl Drop for Registered {
    fn drop(&mut self) {
        #[cfg(unix)]
        if let Some(s) = self.slot.take() {
            imp::forget(s);
        }
    }
}
