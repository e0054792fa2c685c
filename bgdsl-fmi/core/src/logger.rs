//! Messages to the importer through its `logger` callback.
//!
//! Failures (`fmi2Error`, `fmi2Discard`, `fmi2Fatal`) are always reported, whatever
//! `loggingOn` says: a call that fails without a reason helps no one. Warnings and the
//! trace of calls (`logCalls`) obey `loggingOn` and the categories set with
//! `fmi2SetDebugLogging`. Without a logger (a NULL callback) nothing is reported and
//! nothing else changes.

use std::ffi::CString;

use crate::fmi2::{CallbackFunctions, Status};

/// The log categories the FMU declares in `modelDescription.xml`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    /// Calls that return `fmi2Warning`.
    Warning,
    /// Calls that return `fmi2Discard`.
    Discard,
    /// Calls that return `fmi2Error`.
    Error,
    /// Calls that return `fmi2Fatal`.
    Fatal,
    /// Every call, with its arguments (only when switched on).
    Calls,
    /// Every event the FMU handles: its name, time, and the state before and after
    /// (only when switched on).
    Events,
}

impl Category {
    /// Every category, in the order `modelDescription.xml` lists them.
    pub const ALL: [Category; 6] = [
        Category::Warning,
        Category::Discard,
        Category::Error,
        Category::Fatal,
        Category::Calls,
        Category::Events,
    ];

    /// The category's name, as in `modelDescription.xml` and `fmi2SetDebugLogging`.
    pub fn name(self) -> &'static str {
        match self {
            Category::Warning => "logStatusWarning",
            Category::Discard => "logStatusDiscard",
            Category::Error => "logStatusError",
            Category::Fatal => "logStatusFatal",
            Category::Calls => "logCalls",
            Category::Events => "logEvents",
        }
    }

    /// What the category logs, for `modelDescription.xml`.
    pub fn description(self) -> &'static str {
        match self {
            Category::Warning => "calls that return fmi2Warning",
            Category::Discard => "calls that return fmi2Discard (always logged)",
            Category::Error => "calls that return fmi2Error (always logged)",
            Category::Fatal => "calls that return fmi2Fatal (always logged)",
            Category::Calls => "every call to the FMU and its arguments",
            Category::Events => {
                "every event the FMU handles: its name, time, and the state before and after"
            }
        }
    }

    /// The category of a message with this status.
    pub fn for_status(status: Status) -> Category {
        match status {
            Status::Ok | Status::Pending => Category::Calls,
            Status::Warning => Category::Warning,
            Status::Discard => Category::Discard,
            Status::Error => Category::Error,
            Status::Fatal => Category::Fatal,
        }
    }

    /// The category called `name`.
    pub fn from_name(name: &str) -> Option<Category> {
        Category::ALL.into_iter().find(|c| c.name() == name)
    }

    fn bit(self) -> u8 {
        1 << (self as u8)
    }
}

/// The importer's logger, the instance name, and what to log.
#[derive(Debug)]
pub struct Logger {
    callbacks: CallbackFunctions,
    instance_name: CString,
    logging_on: bool,
    enabled: u8,
}

impl Logger {
    /// A logger for the instance `instance_name` (interior NULs dropped) with the
    /// importer's callbacks; `logging_on` as passed to `fmi2Instantiate`, with every
    /// category enabled.
    pub fn new(callbacks: CallbackFunctions, instance_name: &str, logging_on: bool) -> Self {
        Logger {
            callbacks,
            instance_name: c_string(instance_name),
            logging_on,
            enabled: Category::ALL.iter().fold(0, |bits, c| bits | c.bit()),
        }
    }

    /// `fmi2SetDebugLogging`: logging on or off, for the named categories (all of them
    /// when none are named).
    ///
    /// # Errors
    ///
    /// A name that is not a category: the message lists the valid ones. Nothing
    /// changes then.
    pub fn set_debug_logging(
        &mut self,
        logging_on: bool,
        categories: &[String],
    ) -> Result<(), String> {
        let mut bits = 0;
        for name in categories {
            match Category::from_name(name) {
                Some(category) => bits |= category.bit(),
                None => {
                    let valid: Vec<_> = Category::ALL.iter().map(|c| c.name()).collect();
                    return Err(format!(
                        "unknown log category \"{name}\"; the categories are {}",
                        valid.join(", ")
                    ));
                }
            }
        }
        if categories.is_empty() {
            bits = Category::ALL.iter().fold(0, |bits, c| bits | c.bit());
        }
        self.logging_on = logging_on;
        self.enabled = bits;
        Ok(())
    }

    /// Whether a message in `category` would reach the importer (a trace message is
    /// worth formatting only then).
    pub fn wants(&self, category: Category) -> bool {
        if self.callbacks.logger.is_none() {
            return false;
        }
        match category {
            Category::Discard | Category::Error | Category::Fatal => true,
            Category::Warning | Category::Calls | Category::Events => {
                self.logging_on && self.enabled & category.bit() != 0
            }
        }
    }

    /// Sends `message` with `status` to the importer's logger, if it wants it.
    pub fn log(&self, status: Status, message: &str) {
        self.log_in(Category::for_status(status), status, message);
    }

    /// Sends `message` with `status` in `category` to the importer's logger, if it
    /// wants that category.
    pub fn log_in(&self, category: Category, status: Status, message: &str) {
        if !self.wants(category) {
            return;
        }
        let Some(logger) = self.callbacks.logger else {
            return;
        };
        // The message is a printf format for the logger: a literal '%' is written '%%'.
        let text = c_string(&message.replace('%', "%%"));
        let category_name = c_string(category.name());
        // SAFETY: `logger` is the importer's callback, given to fmi2Instantiate for this
        // instance, with the signature the standard fixes; every string is a valid,
        // NUL-terminated C string that outlives the call, and the format has no
        // conversion left (every '%' is doubled), so no variadic argument is read.
        unsafe {
            logger(
                self.callbacks.component_environment,
                self.instance_name.as_ptr(),
                status,
                category_name.as_ptr(),
                text.as_ptr(),
            );
        }
    }
}

/// `text` as a C string, interior NULs dropped.
fn c_string(text: &str) -> CString {
    CString::new(text.replace('\0', "")).unwrap_or_default()
}

#[cfg(test)]
mod should {
    use super::*;

    fn quiet() -> CallbackFunctions {
        CallbackFunctions {
            logger: None,
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: core::ptr::null_mut(),
        }
    }

    #[test]
    fn reject_an_unknown_category_and_keep_the_settings() {
        let mut logger = Logger::new(quiet(), "a", false);
        let error = logger
            .set_debug_logging(true, &["logCalls".into(), "logEverything".into()])
            .unwrap_err();
        assert!(
            error.contains("logEverything") && error.contains("logStatusError"),
            "{error}"
        );
        assert!(!logger.logging_on);
    }

    #[test]
    fn log_nothing_without_a_logger() {
        let logger = Logger::new(quiet(), "a", true);
        assert!(!logger.wants(Category::Error));
        logger.log(Status::Error, "goes nowhere, and does not crash");
    }
}
