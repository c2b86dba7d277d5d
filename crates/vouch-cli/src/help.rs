//! The shape every help page shares: a one-line description, the command's own options, the
//! global options under their own heading, then examples and (on commands that run) the exit
//! codes. [`after_help!`] builds the part after the options, so every page says them the same
//! way.

/// The text after a page's options: `Example:` (or `Examples:`) with one command per line, then, for a command
/// that runs, `Exit codes:` and what each code means for it.
///
/// ```ignore
/// #[command(after_help = after_help!(
///     ["vouch fpl lint examples/fpl/demo.xml"],
///     "0 no warning (or warnings without --strict), 2 usage or I/O error, 3 warnings with --strict"
/// ))]
/// ```
macro_rules! after_help {
    ([$example:literal $(,)?]) => {
        concat!("Example:\n  ", $example, "\n")
    };
    ([$($example:literal),+ $(,)?]) => {
        concat!("Examples:\n", $("  ", $example, "\n",)+)
    };
    ([$example:literal $(,)?], $exit:literal) => {
        concat!("Example:\n  ", $example, "\n\nExit codes: ", $exit)
    };
    ([$($example:literal),+ $(,)?], $exit:literal) => {
        concat!("Examples:\n", $("  ", $example, "\n",)+ "\nExit codes: ", $exit)
    };
}
