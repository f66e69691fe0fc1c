//! The exchange structure's syntax (ISO 10303-21 §5–§10) read into
//! ruststep's syntax tree, for [`read_step`](super::read_step).
//!
//! ruststep's own parser (`ruststep::parser::parse`, nom combinators with
//! verbose errors) read 8 MB/s here: 3–6 ms of a 15–19 ms `fairsurf fill`
//! on a 47 kB file. This one makes one pass over the bytes and gives the
//! same tree as ruststep's on the files the tests compare (Open CASCADE's
//! bundled examples, a revolved face, fairsurf's writer, a text of every
//! token kind), so truck-stepio's `Table::from_data_section` reads it as
//! before. Where ruststep refuses valid files this one reads them: a
//! doubled apostrophe inside a string is one apostrophe (§6.4.3), a list
//! may be empty. It is more lenient than the grammar in a few places: an
//! exponent may be written `e`, white space may stand before a section's
//! `;`, a byte-order mark may lead, and the sections other than DATA
//! (HEADER, ANCHOR, REFERENCE) are only scanned, for their strings,
//! `<URI>`s, comments and `ENDSEC;`. Errors name the line and column (in
//! characters).

use ruststep::ast::{DataSection, EntityInstance, Name, Parameter, Record, SubSuperRecord};

/// Lists nested deeper than this are refused (a file of a million `(`
/// would otherwise overflow the stack); STEP's entities nest a few levels.
const MAX_DEPTH: usize = 64;

/// The first DATA section of an exchange file (none if it has none), every
/// DATA section checked for syntax, the file read to `END-ISO-10303-21;`.
pub(super) fn first_data_section(text: &str) -> Result<Option<DataSection>, String> {
    let mut lx = Lexer {
        text: text.as_bytes(),
        at: 0,
    };
    if lx.text.starts_with("\u{feff}".as_bytes()) {
        lx.at = 3;
    }
    lx.skip();
    lx.expect_word("ISO-10303-21")?;
    lx.expect(b';')?;
    let mut first = None;
    loop {
        lx.skip();
        let start = lx.at;
        let section = "expected a section (HEADER, DATA, …) or END-ISO-10303-21";
        let word = lx.keyword_or_end().map_err(|_| lx.error(section))?;
        match word {
            "END-ISO-10303-21" => {
                lx.expect(b';')?;
                break;
            }
            "HEADER" | "ANCHOR" | "REFERENCE" => {
                lx.expect(b';')?;
                lx.skip_section()?;
            }
            "DATA" => {
                let data = lx.data_section()?;
                first.get_or_insert(data);
            }
            _ => {
                lx.at = start;
                return Err(lx.error(section));
            }
        }
    }
    Ok(first)
}

struct Lexer<'a> {
    text: &'a [u8],
    at: usize,
}

impl<'a> Lexer<'a> {
    /// "line L, column C: message" at the current position.
    fn error(&self, message: &str) -> String {
        let before = &self.text[..self.at.min(self.text.len())];
        let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |k| k + 1);
        let column = String::from_utf8_lossy(&before[line_start..])
            .chars()
            .count()
            + 1;
        let found = match self.peek() {
            None => "the end of the file".to_string(),
            Some(_) => {
                let rest = &self.text[self.at..];
                let n = rest
                    .iter()
                    .take(24)
                    .take_while(|&&b| b != b'\n' && b != b'\r')
                    .count();
                format!("`{}`", String::from_utf8_lossy(&rest[..n]))
            }
        };
        format!("line {line}, column {column}: {message}, found {found}")
    }

    fn peek(&self) -> Option<u8> {
        self.text.get(self.at).copied()
    }

    /// Past white space and comments (`/* … */`).
    fn skip(&mut self) {
        loop {
            while matches!(self.peek(), Some(b) if b.is_ascii_whitespace()) {
                self.at += 1;
            }
            if self.text[self.at..].starts_with(b"/*") {
                match find(&self.text[self.at + 2..], b"*/") {
                    Some(k) => self.at += 2 + k + 2,
                    // Left for the caller to fail on.
                    None => return,
                }
            } else {
                return;
            }
        }
    }

    fn expect(&mut self, byte: u8) -> Result<(), String> {
        self.skip();
        if self.peek() == Some(byte) {
            self.at += 1;
            Ok(())
        } else {
            Err(self.error(&format!("expected `{}`", byte as char)))
        }
    }

    fn expect_word(&mut self, word: &str) -> Result<(), String> {
        if self.text[self.at..].starts_with(word.as_bytes()) {
            self.at += word.len();
            Ok(())
        } else {
            Err(self.error(&format!("expected `{word}`")))
        }
    }

    /// A keyword (`A`–`Z`, `_` then also digits), or `END-ISO-10303-21`.
    fn keyword_or_end(&mut self) -> Result<&'a str, String> {
        if self.text[self.at..].starts_with(b"END-ISO-10303-21") {
            self.at += "END-ISO-10303-21".len();
            return Ok("END-ISO-10303-21");
        }
        self.standard_keyword()
    }

    fn standard_keyword(&mut self) -> Result<&'a str, String> {
        let start = self.at;
        if !matches!(self.peek(), Some(b'A'..=b'Z' | b'_')) {
            return Err(self.error("expected a keyword"));
        }
        while matches!(self.peek(), Some(b'A'..=b'Z' | b'_' | b'0'..=b'9')) {
            self.at += 1;
        }
        let text = self.text;
        Ok(std::str::from_utf8(&text[start..self.at]).expect("ASCII"))
    }

    /// A keyword as ruststep gives it: a user-defined one (`!NAME`) without
    /// its `!`.
    fn keyword(&mut self) -> Result<String, String> {
        if self.peek() == Some(b'!') {
            self.at += 1;
        }
        self.standard_keyword().map(str::to_string)
    }

    /// Past a section's content to its `ENDSEC;`, strings and comments
    /// read as such (an `ENDSEC` inside a string does not end it).
    fn skip_section(&mut self) -> Result<(), String> {
        loop {
            self.skip();
            match self.peek() {
                None => return Err(self.error("expected ENDSEC;")),
                Some(b'\'') => {
                    self.string()?;
                }
                Some(b'/') if self.text[self.at..].starts_with(b"/*") => {
                    return Err(self.error("a comment that does not end"))
                }
                // An ANCHOR's or REFERENCE's `<URI>` (§9, §10): an
                // apostrophe inside it does not start a string (a URI
                // holds no `>` and no white space, RFC 3986).
                Some(b'<') => {
                    let rest = &self.text[self.at..];
                    match rest
                        .iter()
                        .position(|&b| b == b'>' || b.is_ascii_whitespace())
                    {
                        Some(n) if rest[n] == b'>' => self.at += n + 1,
                        _ => return Err(self.error("a <URI> that does not end")),
                    }
                }
                Some(b'A'..=b'Z' | b'_') => {
                    // A whole keyword: `ENDSEC` ends the section, not a
                    // keyword that holds it (`XENDSEC`).
                    if self.standard_keyword()? == "ENDSEC" {
                        return self.expect(b';');
                    }
                }
                Some(_) => self.at += 1,
            }
        }
    }

    /// After `DATA`: an optional parameter list, `;`, the entity instances
    /// and `ENDSEC;`.
    fn data_section(&mut self) -> Result<DataSection, String> {
        self.skip();
        let meta = if self.peek() == Some(b'(') {
            self.at += 1;
            self.parameter_list(b')', 1)?
        } else {
            Vec::new()
        };
        self.expect(b';')?;
        let mut entities = Vec::new();
        loop {
            self.skip();
            if self.text[self.at..].starts_with(b"ENDSEC") {
                self.at += "ENDSEC".len();
                self.expect(b';')?;
                return Ok(DataSection { meta, entities });
            }
            if self.peek() != Some(b'#') {
                return Err(self.error("expected an entity instance `#N = …;` or ENDSEC;"));
            }
            self.at += 1;
            let id = self.digits()?;
            self.expect(b'=')?;
            self.skip();
            let entity = if self.peek() == Some(b'(') {
                self.at += 1;
                let mut records = Vec::new();
                loop {
                    self.skip();
                    if self.peek() == Some(b')') {
                        self.at += 1;
                        break;
                    }
                    records.push(self.record()?);
                }
                EntityInstance::Complex {
                    id,
                    subsuper: SubSuperRecord(records),
                }
            } else {
                EntityInstance::Simple {
                    id,
                    record: self.record()?,
                }
            };
            self.expect(b';')?;
            entities.push(entity);
        }
    }

    /// `KEYWORD(parameters)`.
    fn record(&mut self) -> Result<Record, String> {
        let name = self.keyword()?;
        self.expect(b'(')?;
        let parameters = self.parameter_list(b')', 1)?;
        Ok(Record {
            name,
            parameter: Parameter::List(parameters),
        })
    }

    /// Parameters separated by commas, up to and past `close`.
    fn parameter_list(&mut self, close: u8, depth: usize) -> Result<Vec<Parameter>, String> {
        let mut list = Vec::new();
        self.skip();
        if self.peek() == Some(close) {
            self.at += 1;
            return Ok(list);
        }
        loop {
            list.push(self.parameter(depth)?);
            self.skip();
            match self.peek() {
                Some(b',') => self.at += 1,
                Some(b) if b == close => {
                    self.at += 1;
                    return Ok(list);
                }
                _ => {
                    return Err(self.error(&format!("expected `,` or `{}`", close as char)));
                }
            }
        }
    }

    fn parameter(&mut self, depth: usize) -> Result<Parameter, String> {
        if depth > MAX_DEPTH {
            return Err(self.error(&format!("parameters nested deeper than {MAX_DEPTH}")));
        }
        self.skip();
        let Some(b) = self.peek() else {
            return Err(self.error("expected a parameter"));
        };
        Ok(match b {
            b'$' => {
                self.at += 1;
                Parameter::NotProvided
            }
            b'*' => {
                self.at += 1;
                Parameter::Omitted
            }
            b'(' => {
                self.at += 1;
                Parameter::List(self.parameter_list(b')', depth + 1)?)
            }
            b'\'' => Parameter::String(self.string()?),
            b'.' => {
                self.at += 1;
                let e = self.standard_keyword()?.to_string();
                if self.peek() != Some(b'.') {
                    return Err(self.error("expected `.` ending an enumeration"));
                }
                self.at += 1;
                Parameter::Enumeration(e)
            }
            b'#' | b'@' => {
                self.at += 1;
                if self.peek().is_some_and(|b| b.is_ascii_digit()) {
                    let n = self.digits()?;
                    Parameter::Ref(if b == b'#' {
                        Name::Entity(n)
                    } else {
                        Name::Value(n)
                    })
                } else {
                    let k = self.standard_keyword()?.to_string();
                    Parameter::Ref(if b == b'#' {
                        Name::ConstantEntity(k)
                    } else {
                        Name::ConstantValue(k)
                    })
                }
            }
            b'+' | b'-' | b'0'..=b'9' => self.number()?,
            b'A'..=b'Z' | b'_' | b'!' => {
                let keyword = self.keyword()?;
                self.expect(b'(')?;
                let parameter = self.parameter(depth + 1)?;
                self.expect(b')')?;
                Parameter::Typed {
                    keyword,
                    parameter: Box::new(parameter),
                }
            }
            _ => return Err(self.error("expected a parameter")),
        })
    }

    /// Past one or more decimal digits; where they start.
    fn run_of_digits(&mut self, what: &str) -> Result<usize, String> {
        let start = self.at;
        while self.peek().is_some_and(|b| b.is_ascii_digit()) {
            self.at += 1;
        }
        if start == self.at {
            return Err(self.error(&format!("expected {what}")));
        }
        Ok(start)
    }

    /// An entity or value instance's number.
    fn digits(&mut self) -> Result<u64, String> {
        let start = self.run_of_digits("digits")?;
        let text = self.text;
        let digits = std::str::from_utf8(&text[start..self.at]).expect("ASCII");
        digits.parse().map_err(|_| {
            self.at = start;
            self.error("a number too large for an instance name")
        })
    }

    /// An integer or a real: sign, digits, then `.` digits and an exponent
    /// for a real (§6.4.1–2).
    fn number(&mut self) -> Result<Parameter, String> {
        let negative = match self.peek() {
            Some(b'-') => {
                self.at += 1;
                true
            }
            Some(b'+') => {
                self.at += 1;
                false
            }
            _ => false,
        };
        while self.peek().is_some_and(|b| b.is_ascii_whitespace()) {
            self.at += 1;
        }
        let start = self.run_of_digits("digits")?;
        let real = self.peek() == Some(b'.');
        if real {
            self.at += 1;
            while self.peek().is_some_and(|b| b.is_ascii_digit()) {
                self.at += 1;
            }
            if matches!(self.peek(), Some(b'E' | b'e')) {
                self.at += 1;
                if matches!(self.peek(), Some(b'+' | b'-')) {
                    self.at += 1;
                }
                self.run_of_digits("the exponent's digits")?;
            }
        }
        let all = self.text;
        let text = std::str::from_utf8(&all[start..self.at]).expect("ASCII");
        if real {
            let x: f64 = text
                .parse()
                .map_err(|_| self.error(&format!("`{text}` is not a number")))?;
            Ok(Parameter::Real(if negative { -x } else { x }))
        } else {
            let n: i64 = text.parse().map_err(|_| {
                self.at = start;
                self.error(&format!("`{text}` is too large an integer"))
            })?;
            Ok(Parameter::Integer(if negative { -n } else { n }))
        }
    }

    /// `'…'`, a doubled apostrophe inside read as one; other escapes
    /// (`\X2\…`) are kept as written, as ruststep keeps them.
    fn string(&mut self) -> Result<String, String> {
        let open = self.at;
        self.at += 1;
        let mut s = Vec::new();
        loop {
            match self.peek() {
                None => {
                    self.at = open;
                    return Err(self.error("a string that does not end"));
                }
                Some(b'\'') if self.text.get(self.at + 1) == Some(&b'\'') => {
                    s.push(b'\'');
                    self.at += 2;
                }
                Some(b'\'') => {
                    self.at += 1;
                    return String::from_utf8(s).map_err(|_| {
                        self.at = open;
                        self.error("a string that is not UTF-8")
                    });
                }
                Some(b) => {
                    s.push(b);
                    self.at += 1;
                }
            }
        }
    }
}

/// Where `needle` first occurs in `hay`.
fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fairsurf::bspline::{BSplineSurface, KnotVector, RationalSurface};

    /// ruststep's tree of the file's first DATA section: the reference.
    fn ruststep_tree(text: &str) -> DataSection {
        ruststep::parser::parse(text)
            .expect("ruststep parses it")
            .data
            .swap_remove(0)
    }

    fn ours(text: &str) -> DataSection {
        first_data_section(text).unwrap().expect("a DATA section")
    }

    /// Open CASCADE's files (the bundled examples, a revolved test face)
    /// and fairsurf's own writer (polynomial, rational, collapsed sides)
    /// read to the same tree as ruststep's parser gives, every real equal
    /// to the bit.
    #[test]
    fn files_read_to_ruststeps_tree() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
        let mut texts: Vec<(String, String)> = [
            "examples/cad/fillet_hole.step",
            "examples/cad/rounded_box.step",
            "crates/fairsurf-io/tests/data/revolved.step",
        ]
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(format!("{root}/{p}")).unwrap();
            (p.to_string(), text)
        })
        .collect();
        let wavy = fairsurf::TensorPatch::from_fn(3, 2, |i, j| {
            [
                i as f64 / 3.0,
                j as f64 * 0.7,
                (1.3 * (i * j) as f64).sin() * -1e-3,
            ]
        });
        let cone = fairsurf::TensorPatch::from_fn(2, 2, |i, j| {
            let r = i as f64 / 2.0;
            [r * (j as f64 - 1.0), r, r * r]
        });
        let net = BSplineSurface::from_bezier(&wavy);
        let weights = (0..net.points().len())
            .map(|k| 1.0 + 0.1 * k as f64)
            .collect();
        let rational = RationalSurface::new(net.clone(), weights).unwrap();
        let split = BSplineSurface::new(
            KnotVector::new(3, vec![0., 0., 0., 0., 0.25, 1., 1., 1., 1.]).unwrap(),
            KnotVector::bezier(2),
            (0..15)
                .map(|k| [k as f64 / 7.0, 1e-17 * k as f64, 2.5e8])
                .collect(),
        )
        .unwrap();
        let surfaces: Vec<crate::CadSurface> = vec![
            (&wavy).into(),
            (&cone).into(),
            (&rational).into(),
            (&split).into(),
        ];
        texts.push((
            "fairsurf's".into(),
            crate::step::step_text("x.step", &surfaces),
        ));
        for (name, text) in &texts {
            let tree = ours(text);
            assert!(tree.entities.len() > 50, "{name}");
            assert!(tree == ruststep_tree(text), "{name}");
        }
    }

    /// Every token kind, with comments and line breaks where the syntax
    /// allows them, reads as ruststep reads it; the first of two DATA
    /// sections is the one returned; a header string or keyword holding
    /// `ENDSEC` does not end the header.
    #[test]
    fn every_token_kind_reads_as_ruststep_reads_it() {
        let text = "ISO-10303-21;\nHEADER;\nFILE_NAME('a /* b */ ENDSEC;','x',('y'),$);\nXENDSEC(1);\n/* it's not ENDSEC; */\nENDSEC;\n\
            DATA;\n/* a comment */#1=CARTESIAN_POINT('',(0.,-1.5E-3,+2.25E+02));\n\
            #2 = ( BOUNDED_CURVE() B_SPLINE_CURVE(3,(#1,#1),.UNSPECIFIED.,.F.,.F.)\n\
              !USER_KEY(1, - 7) ) ;\n\
            #3=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.),#4);\n\
            #4=X(*,$,((1,2),(3.5)),#NAMED,@12,@CONST,'', .T. ,/* c */ 6 );\n\
            #5=PRODUCT('Größe \\X2\\00E9\\X0\\','',1.E5,-0.);\n\
            ENDSEC;\nDATA;\n#9=Y(2);\nENDSEC;\nEND-ISO-10303-21;\n";
        let tree = ours(text);
        assert_eq!(tree.entities.len(), 5);
        assert!(tree == ruststep_tree(text));
        let EntityInstance::Simple { record, .. } = &tree.entities[0] else {
            panic!("simple")
        };
        assert_eq!(
            record.parameter,
            Parameter::List(vec![
                Parameter::String(String::new()),
                Parameter::List(vec![
                    Parameter::Real(0.0),
                    Parameter::Real(-1.5e-3),
                    Parameter::Real(225.0),
                ]),
            ])
        );
    }

    /// Never a panic: every 31st prefix of an Open CASCADE file and 400
    /// copies with one byte changed (to each of the syntax's own
    /// characters in turn) read to a tree or an error.
    #[test]
    fn cut_and_changed_files_are_errors_not_panics() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
        let text =
            std::fs::read_to_string(format!("{root}/examples/cad/fillet_hole.step")).unwrap();
        assert!(text.is_ascii());
        for end in (0..text.len()).step_by(31) {
            let _ = first_data_section(&text[..end]);
        }
        let specials = b"#=();,'.$*/ E-+0(";
        let mut x: u64 = 12345;
        for k in 0..400 {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let at = (x >> 33) as usize % text.len();
            let mut bytes = text.clone().into_bytes();
            bytes[at] = specials[k % specials.len()];
            let changed = String::from_utf8(bytes).unwrap();
            let _ = first_data_section(&changed);
        }
    }

    /// Where ruststep refuses valid files: a doubled apostrophe is one
    /// apostrophe (ISO 10303-21 §6.4.3) and a list may be empty (§6.4.6);
    /// leniencies: `e` writes an exponent, a byte-order mark may lead.
    #[test]
    fn doubled_apostrophes_small_exponents_and_empty_lists_are_read() {
        let file = |p: &str| {
            format!(
                "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('a'),'2;1');\n\
                 FILE_NAME('a','b',('c'),('d'),'e','f','g');\nFILE_SCHEMA(('X'));\nENDSEC;\n\
                 DATA;\n#1=A({p});\nENDSEC;\nEND-ISO-10303-21;\n"
            )
        };
        assert!(ruststep::parser::parse(&file("'its',1.5E-3,(1)")).is_ok());
        for refused in ["'it''s'", "1.5e-3", "()"] {
            assert!(
                ruststep::parser::parse(&file(refused)).is_err(),
                "{refused}"
            );
        }
        let text = &file("'it''s',1.5e-3,()");
        // A byte-order mark before it changes nothing.
        assert_eq!(
            first_data_section(&format!("\u{feff}{text}")).unwrap(),
            first_data_section(text).unwrap()
        );
        let EntityInstance::Simple { record, .. } = &ours(text).entities[0] else {
            panic!("simple")
        };
        assert_eq!(
            record.parameter,
            Parameter::List(vec![
                Parameter::String("it's".into()),
                Parameter::Real(1.5e-3),
                Parameter::List(vec![]),
            ])
        );
    }

    /// ANCHOR and REFERENCE sections (ISO 10303-21 §9, §10) are passed
    /// over, an apostrophe inside their `<URI>`s included; a URI that does
    /// not end is an error naming it.
    #[test]
    fn anchor_and_reference_sections_with_uris_are_passed_over() {
        let text = |extra: &str| {
            format!(
                "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('X'));\nENDSEC;\n\
                 ANCHOR;\n<it's> = #1;\n<b> = <https://example.com/a's.stp#c>;\nENDSEC;\n\
                 REFERENCE;\n#20 = <other.stp#it's>;\n{extra}ENDSEC;\n\
                 DATA;\n#1=A('x');\nENDSEC;\nEND-ISO-10303-21;\n"
            )
        };
        let tree = ours(&text(""));
        assert_eq!(tree.entities.len(), 1);
        let e = first_data_section(&text("#21 = <open's;\n")).unwrap_err();
        assert_eq!(
            e,
            "line 11, column 7: a <URI> that does not end, found `<open's;`"
        );
    }

    /// A file with no DATA section is none; each syntax error names its
    /// line and column and what was there, and a file nested a million
    /// lists deep is an error, not a stack overflow.
    #[test]
    fn errors_name_the_place() {
        let wrap =
            |data: &str| format!("ISO-10303-21;\nHEADER;\nENDSEC;\n{data}END-ISO-10303-21;\n");
        assert_eq!(first_data_section(&wrap("")).unwrap(), None);
        let cases = [
            ("solid ascii", "line 1, column 1: expected `ISO-10303-21`, found `solid ascii`"),
            (
                &wrap("DATA;\n#1=A('open);\nENDSEC;\n"),
                "line 5, column 6: a string that does not end, found `'open);`",
            ),
            (
                &wrap("DATA;\n#1=A(1);\n/* open\nENDSEC;\n"),
                "line 6, column 1: expected an entity instance `#N = …;` or ENDSEC;, found `/* open`",
            ),
            (
                &wrap("DATA;\n#1=A(1,);\nENDSEC;\n"),
                "line 5, column 8: expected a parameter, found `);`",
            ),
            (
                &wrap("DATA;\n#1=A(1)\n#2=B(2);\nENDSEC;\n"),
                "line 6, column 1: expected `;`, found `#2=B(2);`",
            ),
            (
                &wrap("DATA;\n#1=A(1 2);\nENDSEC;\n"),
                "line 5, column 8: expected `,` or `)`, found `2);`",
            ),
            (
                &wrap("DATA;\n#1=A(99999999999999999999);\nENDSEC;\n"),
                "line 5, column 6: `99999999999999999999` is too large an integer",
            ),
            (
                &wrap("DATA;\n#1=A(.T);\nENDSEC;\n"),
                "line 5, column 8: expected `.` ending an enumeration, found `);`",
            ),
            (
                &wrap("DATA;\n#1=A(1.5E);\nENDSEC;\n"),
                "line 5, column 10: expected the exponent's digits, found `);`",
            ),
            (&wrap("DATA;\n#1=A(1);\n"), "line 6, column 1: expected an entity instance"),
            (
                "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\nENDSEC;\n",
                "line 6, column 1: expected a section (HEADER, DATA, …) or END-ISO-10303-21, \
                 found the end of the file",
            ),
            (
                &wrap("DATA;\n#1=A('Größe',1 2);\nENDSEC;\n"),
                "line 5, column 16: expected `,` or `)`, found `2);`",
            ),
            (
                &wrap("DATA;\n#18446744073709551616=A(1);\nENDSEC;\n"),
                "line 5, column 2: a number too large for an instance name",
            ),
        ];
        for (text, want) in cases {
            let e = first_data_section(text).unwrap_err();
            assert!(e.starts_with(want), "{e}\nwanted {want}");
        }
        for (open, n) in [("(", 1_000_000), ("B(", 100)] {
            let nested = format!("{}1{}", open.repeat(n), ")".repeat(n));
            let text = wrap(&format!("DATA;\n#1=A({nested});\nENDSEC;\n"));
            let e = first_data_section(&text).unwrap_err();
            assert!(e.contains("nested deeper than 64"), "{e}");
        }
    }
}
