//! Which DUT signal stands for each golden output: the one of the same name in the DUT's
//! top scope, never an internal signal that happens to share the name.
//!
//! The DUT's top scope is the one named by `--dut-scope` (a dotted path such as
//! `tt_testbench.dut`), or else the shallowest scope of the DUT dump that declares any of
//! the golden output names, the one declaring the most of them when several are equally
//! shallow (`tooltouch.outputs` beats `tooltouch.inputs`, which holds only the pin
//! `contact`). Every golden output must be declared in that scope itself: one found only
//! deeper (a submodule's port such as `u_measure.count`) or elsewhere is an error listing
//! where the name was found, and two equally good top scopes, or one name declared twice
//! in it, are an error listing the candidates. So a renamed or missing port can never pass
//! on an internal signal.

use super::BadInput;
use crate::vcd::{Declarations, Signal};

/// How many candidate paths an error lists.
const LISTED: usize = 8;

/// The dotted path of `signal` (`scope.name`).
pub fn path_of(signal: &Signal) -> String {
    signal
        .scope
        .iter()
        .chain(std::iter::once(&signal.name))
        .cloned()
        .collect::<Vec<_>>()
        .join(".")
}

fn scope_text(scope: &[String]) -> String {
    if scope.is_empty() {
        "(the top level)".into()
    } else {
        scope.join(".")
    }
}

fn listed(mut paths: Vec<String>) -> String {
    paths.sort();
    paths.dedup();
    let more = paths.len().saturating_sub(LISTED);
    paths.truncate(LISTED);
    let mut text = paths
        .iter()
        .map(|p| format!("`{p}`"))
        .collect::<Vec<_>>()
        .join(", ");
    if more > 0 {
        text.push_str(&format!(" and {more} more"));
    }
    text
}

/// The DUT's top scope and, for each of `names` in order, the DUT signal compared with it.
#[derive(Debug)]
pub struct Resolution<'a> {
    /// The scope path (empty: the dump's top level).
    pub scope: Vec<String>,
    /// One signal per golden name.
    pub signals: Vec<&'a Signal>,
}

impl Resolution<'_> {
    /// The scope as a dotted path.
    pub fn scope_text(&self) -> String {
        scope_text(&self.scope)
    }
}

/// Resolves every golden output name of `names` in the DUT dump `d` (named `dn` in
/// errors): see the module documentation. `dut_scope` is a dotted scope path.
pub fn resolve<'a>(
    names: &[&str],
    d: &'a Declarations,
    dut_scope: Option<&str>,
    dn: &str,
) -> Result<Resolution<'a>, BadInput> {
    // Scopes declaring golden names, with how many distinct names each declares.
    let mut scopes: Vec<(&[String], Vec<&str>)> = Vec::new();
    for s in d
        .signals
        .iter()
        .filter(|s| names.contains(&s.name.as_str()))
    {
        match scopes.iter_mut().find(|(sc, _)| *sc == s.scope.as_slice()) {
            Some((_, held)) => {
                if !held.contains(&s.name.as_str()) {
                    held.push(&s.name);
                }
            }
            None => scopes.push((&s.scope, vec![&s.name])),
        }
    }
    let describe =
        |sc: &[String], held: usize| format!("`{}` ({held} of {})", scope_text(sc), names.len());
    let scope: Vec<String> = match dut_scope {
        Some(given) => {
            let wanted: Vec<String> = given
                .split('.')
                .filter(|p| !p.is_empty())
                .map(str::to_string)
                .collect();
            if !d.signals.iter().any(|s| s.scope == wanted) {
                let mut holding: Vec<_> = scopes.iter().collect();
                holding.sort_by_key(|(sc, held)| (sc.len(), usize::MAX - held.len()));
                let found: Vec<String> = holding
                    .iter()
                    .take(LISTED)
                    .map(|(sc, held)| describe(sc, held.len()))
                    .collect();
                return Err(BadInput(format!(
                    "{dn}: --dut-scope `{given}`: no such scope; scopes declaring golden outputs: {}",
                    if found.is_empty() {
                        "none".to_string()
                    } else {
                        found.join(", ")
                    }
                )));
            }
            wanted
        }
        None => {
            let Some(depth) = scopes.iter().map(|(sc, _)| sc.len()).min() else {
                return Err(BadInput(format!(
                    "{dn}: declares none of the golden outputs ({})",
                    names.join(" ")
                )));
            };
            let most = scopes
                .iter()
                .filter(|(sc, _)| sc.len() == depth)
                .map(|(_, held)| held.len())
                .max()
                .unwrap_or(0);
            let best: Vec<_> = scopes
                .iter()
                .filter(|(sc, held)| sc.len() == depth && held.len() == most)
                .collect();
            if best.len() > 1 {
                return Err(BadInput(format!(
                    "{dn}: ambiguous DUT scope: {} each declare {most} of the golden outputs at the same depth; name the DUT's with --dut-scope",
                    best.iter()
                        .map(|(sc, held)| describe(sc, held.len()))
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
            best[0].0.to_vec()
        }
    };
    let mut signals = Vec::with_capacity(names.len());
    for name in names {
        let here: Vec<&Signal> = d
            .signals
            .iter()
            .filter(|s| s.name == *name && s.scope == scope)
            .collect();
        match here.as_slice() {
            [one] => signals.push(*one),
            [first, rest @ ..] => {
                if rest.iter().all(|s| s.id == first.id) {
                    signals.push(*first);
                } else {
                    return Err(BadInput(format!(
                        "{dn}: `{name}` is declared {} times in the DUT scope `{}` with different identifiers (lines {}): ambiguous",
                        here.len(),
                        scope_text(&scope),
                        here.iter()
                            .map(|s| s.line.to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )));
                }
            }
            [] => {
                let elsewhere: Vec<String> = d
                    .signals
                    .iter()
                    .filter(|s| s.name == *name)
                    .map(path_of)
                    .collect();
                let how = if dut_scope.is_some() {
                    "given by --dut-scope"
                } else {
                    "the shallowest declaring golden outputs; --dut-scope names another"
                };
                return Err(BadInput(if elsewhere.is_empty() {
                    format!(
                        "{dn}: no signal named `{name}` (expected from the golden trace) in the DUT scope `{}` ({how}), nor anywhere else",
                        scope_text(&scope)
                    )
                } else {
                    format!(
                        "{dn}: no signal named `{name}` (expected from the golden trace) in the DUT scope `{}` ({how}); found only at {}, which is not compared: a port of the DUT's top scope must carry the name",
                        scope_text(&scope),
                        listed(elsewhere)
                    )
                }));
            }
        }
    }
    Ok(Resolution { scope, signals })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vcd::VcdReader;

    fn declarations(scopes: &[(&str, &[&str])]) -> Declarations {
        let mut text = String::new();
        let mut code = 0u8;
        for (scope, names) in scopes {
            for part in scope.split('.') {
                text.push_str(&format!("$scope module {part} $end\n"));
            }
            for n in *names {
                text.push_str(&format!(
                    "$var wire 1 {} {n} $end\n",
                    char::from(b'!' + code)
                ));
                code += 1;
            }
            for _ in scope.split('.') {
                text.push_str("$upscope $end\n");
            }
        }
        text.push_str("$enddefinitions $end\n");
        VcdReader::new(text.as_bytes(), "d.vcd")
            .unwrap()
            .declarations()
            .clone()
    }

    #[test]
    fn the_top_scope_is_the_shallowest_then_the_fullest() {
        let d = declarations(&[
            ("tb.dut", &["a", "b"]),
            ("tb.dut.inner", &["a", "b"]),
            ("tb.pins", &["a"]),
        ]);
        let r = resolve(&["a", "b"], &d, None, "d.vcd").unwrap();
        assert_eq!(r.scope_text(), "tb.dut");
        assert_eq!(path_of(r.signals[1]), "tb.dut.b");
        // Named explicitly, an inner scope is taken as asked.
        let r = resolve(&["a", "b"], &d, Some("tb.dut.inner"), "d.vcd").unwrap();
        assert_eq!(path_of(r.signals[0]), "tb.dut.inner.a");
    }

    #[test]
    fn an_equal_tie_is_ambiguous_and_lists_both() {
        let d = declarations(&[("tb.u1", &["a", "b"]), ("tb.u2", &["a", "b"])]);
        let e = resolve(&["a", "b"], &d, None, "d.vcd").unwrap_err().0;
        assert!(
            e.contains("ambiguous")
                && e.contains("`tb.u1` (2 of 2)")
                && e.contains("`tb.u2` (2 of 2)"),
            "{e}"
        );
    }

    #[test]
    fn a_name_only_inside_is_refused_with_where_it_is() {
        let d = declarations(&[("tb.dut", &["a"]), ("tb.dut.inner", &["a", "b"])]);
        let e = resolve(&["a", "b"], &d, None, "d.vcd").unwrap_err().0;
        assert!(
            e.contains("no signal named `b`")
                && e.contains("`tb.dut.inner.b`")
                && e.contains("not compared"),
            "{e}"
        );
    }
}
