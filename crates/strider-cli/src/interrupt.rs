//! Ctrl-C and SIGTERM. A command that can wind down (`run`, `replay`, `bench`) takes the
//! cancellation flag with [`winds_down`]: the first signal requests it, the work stops at its
//! next check and keeps what it finished. Otherwise, and on a second signal, the process exits
//! at once (every file it wrote is whole: files are written atomically).

use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

use strider_experiments::cancel::Cancel;

/// Exit code of an interrupted command (128 + SIGINT, the shells' convention).
pub const EXIT_CODE: u8 = 130;

/// Whether the running command checks the flag.
static WINDS_DOWN: AtomicBool = AtomicBool::new(false);

fn flag() -> &'static Cancel {
    static FLAG: OnceLock<Cancel> = OnceLock::new();
    FLAG.get_or_init(Cancel::new)
}

/// The cancellation flag, for a command that checks it from now on.
pub fn winds_down() -> &'static Cancel {
    WINDS_DOWN.store(true, Ordering::SeqCst);
    flag()
}

/// Installs the signal handler (without one, e.g. when a handler is already set, signals keep
/// their default action).
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        let cancel = flag();
        if WINDS_DOWN.load(Ordering::SeqCst) && !cancel.requested() {
            cancel.request();
            return;
        }
        let what = if cancel.requested() {
            "stopped at once by a second signal; files already finished stay, the work in progress is lost"
        } else {
            "stopped at once; files already written are whole, nothing else was kept"
        };
        eprintln!("interrupted: {what}");
        std::process::exit(i32::from(EXIT_CODE));
    });
}
