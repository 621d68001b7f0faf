//! A static reader of the Python that launch files hold: roslaunch's
//! `$(eval ...)` expressions and ROS 2 launch.py files. Text is tokenised
//! ([`lex`]), parsed into a small AST ([`parse`]) and evaluated over Python's
//! value semantics ([`eval`], [`value`], with a closed list of builtins,
//! `math` and `str`/`list`/`dict` methods in [`builtins`], [`methods`]).
//! Nothing is ever executed, imported or looked up outside the text: what a
//! name means is the host's to say (launch args for roslaunch, the file's own
//! bindings for launch.py), and anything outside the subset is an error (or,
//! for launch.py, a value known to be unknown) that names the construct and
//! its line.

pub mod budget;
pub mod builtins;
mod caps;
pub mod eval;
pub mod lex;
pub mod methods;
pub mod ops;
pub mod parse;
pub mod value;

pub use eval::{Eval, Host};
pub use parse::{expression, module, Expr, ExprKind, Stmt};
pub use value::{Func, Record, Value};
