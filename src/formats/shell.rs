//! Shell command lines, split the way `sh` splits them far enough to find one
//! `static_transform_publisher` command each: words (quotes and backslash
//! escapes honoured), a `#` that starts a word begins a comment, and the
//! control operators `;`, `&`, `&&`, `|`, `||`, the subshell and group
//! brackets `(`, `)`, `{`, `}` end a command when they start a word or end
//! one before a blank (`cmd &`, `(cmd)`, `cmd; next`). Nothing is expanded: a `$(...)`
//! or `${...}` stays in its word (the publisher reader refuses it).

/// One simple command: its words and the byte offset of its first word in
/// the line.
#[derive(Debug, Clone, PartialEq)]
pub struct Command {
    /// The words, quotes removed.
    pub words: Vec<String>,
    /// Byte offset of the first word in the line.
    pub offset: usize,
}

#[derive(Default)]
struct Splitter {
    commands: Vec<Command>,
    words: Vec<String>,
    word: String,
    /// A word is open (possibly empty: `''`).
    open: bool,
    start: Option<usize>,
}

impl Splitter {
    fn end_word(&mut self) {
        if self.open {
            self.words.push(std::mem::take(&mut self.word));
            self.open = false;
        }
    }
    fn end_command(&mut self) {
        self.end_word();
        if !self.words.is_empty() {
            self.commands.push(Command {
                words: std::mem::take(&mut self.words),
                offset: self.start.unwrap_or(0),
            });
        }
        self.start = None;
    }
    fn push(&mut self, at: usize, c: char) {
        if !self.open {
            self.open = true;
            if self.start.is_none() {
                self.start = Some(at);
            }
        }
        self.word.push(c);
    }
    fn open_empty(&mut self, at: usize) {
        if !self.open {
            self.open = true;
            if self.start.is_none() {
                self.start = Some(at);
            }
        }
    }
}

/// Whether `c` may follow a control operator that ends a word.
fn boundary(c: char) -> bool {
    c.is_whitespace() || matches!(c, ';' | '&' | '|' | '(' | ')')
}

/// The simple commands of one logical line (continuations already joined).
/// A control operator inside a word (`a|b`, `x;y`) is kept in the word: the
/// files are often command lines saved as text, and frame names in hostile
/// or odd files keep what they hold.
pub fn commands(line: &str) -> Vec<Command> {
    let mut s = Splitter::default();
    let mut it = line.char_indices().peekable();
    while let Some((i, c)) = it.next() {
        match c {
            '\'' => {
                s.open_empty(i);
                for (_, q) in it.by_ref() {
                    if q == '\'' {
                        break;
                    }
                    s.word.push(q);
                }
            }
            '"' => {
                s.open_empty(i);
                while let Some((_, q)) = it.next() {
                    match q {
                        '"' => break,
                        '\\' => {
                            if let Some((_, n)) = it.next() {
                                s.word.push(n);
                            }
                        }
                        _ => s.word.push(q),
                    }
                }
            }
            '\\' => {
                if let Some((_, n)) = it.next() {
                    s.push(i, n);
                }
            }
            '#' if !s.open => break,
            ';' | '&' | '|' | '(' | ')'
                if !s.open || it.peek().is_none_or(|(_, n)| boundary(*n)) =>
            {
                s.end_command()
            }
            '{' | '}' if !s.open && it.peek().is_none_or(|(_, n)| n.is_whitespace()) => {
                s.end_command()
            }
            c if c.is_whitespace() => s.end_word(),
            c => s.push(i, c),
        }
    }
    s.end_command();
    s.commands
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(line: &str) -> Vec<Vec<String>> {
        commands(line).into_iter().map(|c| c.words).collect()
    }

    #[test]
    fn operators_brackets_and_comments_end_commands() {
        assert_eq!(
            words("(sleep 1 && a 'b c' \"d\\\"e\") & f; g || h # i ; j"),
            vec![
                vec!["sleep", "1"],
                vec!["a", "b c", "d\"e"],
                vec!["f"],
                vec!["g"],
                vec!["h"],
            ]
        );
        assert_eq!(words("x|<b> y;z &"), vec![vec!["x|<b>", "y;z"]]);
        assert_eq!(words("{ a; } | b#c"), vec![vec!["a"], vec!["b#c"]]);
        assert_eq!(commands("  x y")[0].offset, 2);
        assert!(commands("# all comment").is_empty());
    }
}
