//! Where a serialisable value holds a number that is not finite.
//!
//! JSON has no NaN or infinity: `serde_json` writes them as `null`, so a report with a NaN
//! serialises and parses back without complaint and the NaN is silently lost. This walks the
//! value through serde instead and names every non-finite float by its path, e.g.
//! `models[0].class_table[2].cost`.

use serde::Serialize;
use serde::ser::{self, Impossible};
use std::fmt;

/// At most this many paths are named; the count goes on.
const MAX_PATHS: usize = 8;

/// The non-finite numbers of a value: how many, and the paths of the first few.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NonFinite {
    /// Non-finite floats found.
    pub count: usize,
    /// Paths of the first of them.
    pub paths: Vec<String>,
}

impl NonFinite {
    /// Walks `value`; an error names what serde could not walk (a serialiser error of the value
    /// itself, e.g. a map key that is not a string or a number).
    pub fn of(value: &impl Serialize) -> Result<Self, String> {
        let mut w = Walker::default();
        value.serialize(&mut w).map_err(|e| e.0)?;
        Ok(w.found)
    }
}

impl fmt::Display for NonFinite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} non-finite numbers at {}",
            self.count,
            self.paths.join(", ")
        )?;
        if self.count > self.paths.len() {
            write!(f, ", …")?;
        }
        Ok(())
    }
}

#[derive(Debug)]
struct WalkError(String);

impl fmt::Display for WalkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WalkError {}

impl ser::Error for WalkError {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Self(msg.to_string())
    }
}

/// The path to the value being walked, and the counters of the sequences on it.
#[derive(Default)]
struct Walker {
    path: Vec<String>,
    index: Vec<usize>,
    key: Option<String>,
    found: NonFinite,
}

impl Walker {
    fn float(&mut self, v: f64) {
        if v.is_finite() {
            return;
        }
        self.found.count += 1;
        if self.found.paths.len() < MAX_PATHS {
            let p = self.path.concat();
            self.found.paths.push(format!(
                "{} ({v})",
                if p.is_empty() {
                    "."
                } else {
                    p.trim_start_matches('.')
                }
            ));
        }
    }

    fn child<T: ?Sized + Serialize>(&mut self, seg: String, v: &T) -> Result<(), WalkError> {
        self.path.push(seg);
        let r = v.serialize(&mut *self);
        self.path.pop();
        r
    }

    fn element<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), WalkError> {
        let i = self.index.last().copied().unwrap_or(0);
        if let Some(last) = self.index.last_mut() {
            *last += 1;
        }
        self.child(format!("[{i}]"), v)
    }

    fn open(&mut self) -> &mut Self {
        self.index.push(0);
        self
    }

    fn close(&mut self) {
        self.index.pop();
    }
}

/// Map keys as text for paths (strings, numbers, booleans, chars and unit variants).
struct KeyText;

macro_rules! key_display {
    ($($f:ident: $t:ty),*) => {
        $(fn $f(self, v: $t) -> Result<String, WalkError> { Ok(v.to_string()) })*
    };
}

impl ser::Serializer for KeyText {
    type Ok = String;
    type Error = WalkError;
    type SerializeSeq = Impossible<String, WalkError>;
    type SerializeTuple = Impossible<String, WalkError>;
    type SerializeTupleStruct = Impossible<String, WalkError>;
    type SerializeTupleVariant = Impossible<String, WalkError>;
    type SerializeMap = Impossible<String, WalkError>;
    type SerializeStruct = Impossible<String, WalkError>;
    type SerializeStructVariant = Impossible<String, WalkError>;
    key_display!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
        serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32,
        serialize_u64: u64, serialize_f32: f32, serialize_f64: f64, serialize_char: char,
        serialize_str: &str);
    fn serialize_bytes(self, _: &[u8]) -> Result<String, WalkError> {
        Ok("<bytes>".into())
    }
    fn serialize_none(self) -> Result<String, WalkError> {
        Ok("null".into())
    }
    fn serialize_some<T: ?Sized + Serialize>(self, v: &T) -> Result<String, WalkError> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<String, WalkError> {
        Ok("()".into())
    }
    fn serialize_unit_struct(self, name: &'static str) -> Result<String, WalkError> {
        Ok(name.into())
    }
    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
    ) -> Result<String, WalkError> {
        Ok(variant.into())
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<String, WalkError> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<String, WalkError> {
        Err(WalkError("a map key is an enum with data".into()))
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, WalkError> {
        Err(WalkError("a map key is a sequence".into()))
    }
    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, WalkError> {
        Err(WalkError("a map key is a tuple".into()))
    }
    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, WalkError> {
        Err(WalkError("a map key is a tuple struct".into()))
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, WalkError> {
        Err(WalkError("a map key is an enum with data".into()))
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, WalkError> {
        Err(WalkError("a map key is a map".into()))
    }
    fn serialize_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStruct, WalkError> {
        Err(WalkError("a map key is a struct".into()))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, WalkError> {
        Err(WalkError("a map key is an enum with data".into()))
    }
}

macro_rules! leaf {
    ($($f:ident: $t:ty),*) => {
        $(fn $f(self, _: $t) -> Result<(), WalkError> { Ok(()) })*
    };
}

impl<'a> ser::Serializer for &'a mut Walker {
    type Ok = ();
    type Error = WalkError;
    type SerializeSeq = &'a mut Walker;
    type SerializeTuple = &'a mut Walker;
    type SerializeTupleStruct = &'a mut Walker;
    type SerializeTupleVariant = &'a mut Walker;
    type SerializeMap = &'a mut Walker;
    type SerializeStruct = &'a mut Walker;
    type SerializeStructVariant = &'a mut Walker;
    leaf!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
        serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32,
        serialize_u64: u64, serialize_char: char, serialize_str: &str, serialize_bytes: &[u8]);
    fn serialize_f32(self, v: f32) -> Result<(), WalkError> {
        self.float(v as f64);
        Ok(())
    }
    fn serialize_f64(self, v: f64) -> Result<(), WalkError> {
        self.float(v);
        Ok(())
    }
    fn serialize_none(self) -> Result<(), WalkError> {
        Ok(())
    }
    fn serialize_some<T: ?Sized + Serialize>(self, v: &T) -> Result<(), WalkError> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), WalkError> {
        Ok(())
    }
    fn serialize_unit_struct(self, _: &'static str) -> Result<(), WalkError> {
        Ok(())
    }
    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
    ) -> Result<(), WalkError> {
        Ok(())
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<(), WalkError> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        v: &T,
    ) -> Result<(), WalkError> {
        self.child(format!(".{variant}"), v)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self, WalkError> {
        Ok(self.open())
    }
    fn serialize_tuple(self, _: usize) -> Result<Self, WalkError> {
        Ok(self.open())
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Self, WalkError> {
        Ok(self.open())
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Self, WalkError> {
        self.path.push(format!(".{variant}"));
        Ok(self.open())
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self, WalkError> {
        Ok(self)
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, WalkError> {
        Ok(self)
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Self, WalkError> {
        self.path.push(format!(".{variant}"));
        Ok(self)
    }
}

impl ser::SerializeSeq for &mut Walker {
    type Ok = ();
    type Error = WalkError;
    fn serialize_element<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), WalkError> {
        self.element(v)
    }
    fn end(self) -> Result<(), WalkError> {
        self.close();
        Ok(())
    }
}

impl ser::SerializeTuple for &mut Walker {
    type Ok = ();
    type Error = WalkError;
    fn serialize_element<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), WalkError> {
        self.element(v)
    }
    fn end(self) -> Result<(), WalkError> {
        self.close();
        Ok(())
    }
}

impl ser::SerializeTupleStruct for &mut Walker {
    type Ok = ();
    type Error = WalkError;
    fn serialize_field<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), WalkError> {
        self.element(v)
    }
    fn end(self) -> Result<(), WalkError> {
        self.close();
        Ok(())
    }
}

impl ser::SerializeTupleVariant for &mut Walker {
    type Ok = ();
    type Error = WalkError;
    fn serialize_field<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), WalkError> {
        self.element(v)
    }
    fn end(self) -> Result<(), WalkError> {
        self.close();
        self.path.pop();
        Ok(())
    }
}

impl ser::SerializeMap for &mut Walker {
    type Ok = ();
    type Error = WalkError;
    fn serialize_key<T: ?Sized + Serialize>(&mut self, k: &T) -> Result<(), WalkError> {
        self.key = Some(k.serialize(KeyText)?);
        Ok(())
    }
    fn serialize_value<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), WalkError> {
        let key = self.key.take().unwrap_or_default();
        self.child(format!(".{key}"), v)
    }
    fn end(self) -> Result<(), WalkError> {
        Ok(())
    }
}

impl ser::SerializeStruct for &mut Walker {
    type Ok = ();
    type Error = WalkError;
    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        v: &T,
    ) -> Result<(), WalkError> {
        self.child(format!(".{key}"), v)
    }
    fn end(self) -> Result<(), WalkError> {
        Ok(())
    }
}

impl ser::SerializeStructVariant for &mut Walker {
    type Ok = ();
    type Error = WalkError;
    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        v: &T,
    ) -> Result<(), WalkError> {
        self.child(format!(".{key}"), v)
    }
    fn end(self) -> Result<(), WalkError> {
        self.path.pop();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::NonFinite;
    use std::collections::BTreeMap;

    #[derive(serde::Serialize)]
    struct Inner {
        cost: f64,
        var: Option<f32>,
    }

    #[derive(serde::Serialize)]
    enum Kind {
        Pair(f64, f64),
        Named { z: f64 },
    }

    #[derive(serde::Serialize)]
    struct Report {
        n: usize,
        #[serde(flatten)]
        inner: Inner,
        classes: Vec<Inner>,
        by_name: BTreeMap<String, [f64; 2]>,
        kinds: Vec<Kind>,
    }

    #[test]
    fn every_non_finite_number_is_named_by_its_path() {
        let r = Report {
            n: 3,
            inner: Inner {
                cost: 1.0,
                var: Some(f32::NAN),
            },
            classes: vec![
                Inner {
                    cost: 2.0,
                    var: None,
                },
                Inner {
                    cost: f64::INFINITY,
                    var: Some(0.5),
                },
            ],
            by_name: [("fast".to_string(), [0.0, f64::NEG_INFINITY])].into(),
            kinds: vec![Kind::Pair(1.0, f64::NAN), Kind::Named { z: f64::NAN }],
        };
        let found = NonFinite::of(&r).unwrap();
        assert_eq!(found.count, 5);
        assert_eq!(
            found.paths,
            [
                "var (NaN)",
                "classes[1].cost (inf)",
                "by_name.fast[1] (-inf)",
                "kinds[0].Pair[1] (NaN)",
                "kinds[1].Named.z (NaN)"
            ]
        );
        let fine = Inner {
            cost: 1.0,
            var: None,
        };
        assert_eq!(NonFinite::of(&fine).unwrap().count, 0);
        assert_eq!(NonFinite::of(&f64::NAN).unwrap().paths, [". (NaN)"]);
    }
}
