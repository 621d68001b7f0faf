//! Symbol and macro tables, chained as Python xacro chains them: a macro call
//! opens a child table of the *caller's* table (dynamic scope), an include
//! with `ns` opens a namespace table; lookups walk to the root.
//!
//! Properties are lazy: the text of `value` is kept and evaluated at first use
//! in the table that defines it (then cached), so a property may name another
//! defined after it; a definition that reaches itself is refused.
//!
//! The property tables hold values of any type `V` (`value::Value`, whose
//! namespaces hold tables in turn: `value` names the instance).

use super::tree::{Elem, Src};
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

/// A property as stored.
#[derive(Debug, Clone)]
pub enum Slot<V> {
    /// Text not yet evaluated, with where it was defined.
    Lazy(String, Src),
    /// Being evaluated now (a lookup reaching it is a circular definition).
    Busy,
    Val(V),
}

/// One table of bindings (properties or macros by name) in the chain.
#[derive(Debug)]
pub struct Bindings<V> {
    vars: RefCell<HashMap<String, Slot<V>>>,
    pub parent: Option<Scope<V>>,
    /// A namespace opened by `xacro:include ns` (for `scope="parent"`).
    pub is_ns: bool,
}

pub type Scope<V> = Rc<Bindings<V>>;

impl<V: Clone> Bindings<V> {
    pub fn root() -> Scope<V> {
        Rc::new(Bindings {
            vars: RefCell::new(HashMap::new()),
            parent: None,
            is_ns: false,
        })
    }

    pub fn child(parent: &Scope<V>, is_ns: bool) -> Scope<V> {
        Rc::new(Bindings {
            vars: RefCell::new(HashMap::new()),
            parent: Some(parent.clone()),
            is_ns,
        })
    }

    /// The table in the chain that holds `name`, and its slot.
    pub fn find(self: &Rc<Self>, name: &str) -> Option<(Scope<V>, Slot<V>)> {
        let mut t = self.clone();
        loop {
            if let Some(s) = t.vars.borrow().get(name) {
                return Some((t.clone(), s.clone()));
            }
            let p = t.parent.clone()?;
            t = p;
        }
    }

    pub fn contains(self: &Rc<Self>, name: &str) -> bool {
        self.find(name).is_some()
    }

    pub fn set(&self, name: &str, slot: Slot<V>) {
        self.vars.borrow_mut().insert(name.to_string(), slot);
    }

    /// `remove="true"`: drop the name from this table and its parents.
    pub fn remove(self: &Rc<Self>, name: &str) {
        let mut t = Some(self.clone());
        while let Some(x) = t {
            x.vars.borrow_mut().remove(name);
            t = x.parent.clone();
        }
    }

    /// The outermost table (`scope="global"`).
    pub fn top(self: &Rc<Self>) -> Scope<V> {
        let mut t = self.clone();
        while let Some(p) = t.parent.clone() {
            t = p;
        }
        t
    }
}

/// A macro definition: parameter names in order (`*x` / `**x` for blocks) and
/// their defaults: (forward from the caller's scope with `^`, default text).
#[derive(Debug)]
pub struct Macro {
    pub name: String,
    pub params: Vec<String>,
    pub defaults: HashMap<String, (bool, Option<String>)>,
    pub body: Rc<Elem>,
}

#[derive(Debug, Clone)]
pub enum MacroEntry {
    Macro(Rc<Macro>),
    Ns(MacroScope),
}

#[derive(Debug, Default)]
pub struct MacroTable {
    map: RefCell<HashMap<String, MacroEntry>>,
    parent: Option<MacroScope>,
}

pub type MacroScope = Rc<MacroTable>;

impl MacroTable {
    pub fn root() -> MacroScope {
        Rc::new(MacroTable::default())
    }

    pub fn child(parent: &MacroScope) -> MacroScope {
        Rc::new(MacroTable {
            map: RefCell::new(HashMap::new()),
            parent: Some(parent.clone()),
        })
    }

    pub fn get(self: &Rc<Self>, name: &str) -> Option<MacroEntry> {
        let mut t = self.clone();
        loop {
            if let Some(m) = t.map.borrow().get(name) {
                return Some(m.clone());
            }
            let p = t.parent.clone()?;
            t = p;
        }
    }

    pub fn set(&self, name: &str, m: MacroEntry) {
        self.map.borrow_mut().insert(name.to_string(), m);
    }

    /// Names defined anywhere in the chain, for "did you mean" messages.
    pub fn names(self: &Rc<Self>) -> Vec<String> {
        let mut out = Vec::new();
        let mut t = Some(self.clone());
        while let Some(x) = t {
            out.extend(x.map.borrow().keys().cloned());
            t = x.parent.clone();
        }
        out.sort();
        out.dedup();
        out
    }
}
