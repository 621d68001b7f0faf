//! The top-level field names of a report, without serialising it: a
//! serializer that accepts a struct, records each field's name and never
//! looks at its value. Anything else is "not found" (the caller then asks
//! the JSON tree, as before: only small reports are maps or values).

use serde::ser::{self, Impossible, Serialize, SerializeStruct};
use std::fmt;

/// Not a plain struct.
#[derive(Debug)]
pub struct NotStruct;

impl fmt::Display for NotStruct {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("not a struct")
    }
}

impl std::error::Error for NotStruct {}

impl ser::Error for NotStruct {
    fn custom<T: fmt::Display>(_: T) -> Self {
        NotStruct
    }
}

/// The probe: `Some(names)` for a struct.
pub struct Keys;

/// The fields met so far.
pub struct Fields(Vec<String>);

impl SerializeStruct for Fields {
    type Ok = Option<Vec<String>>;
    type Error = NotStruct;
    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        _: &T,
    ) -> Result<(), NotStruct> {
        self.0.push(key.to_string());
        Ok(())
    }
    fn skip_field(&mut self, _: &'static str) -> Result<(), NotStruct> {
        Ok(())
    }
    fn end(self) -> Result<Self::Ok, NotStruct> {
        Ok(Some(self.0))
    }
}

macro_rules! not_struct {
    ($($name:ident($($t:ty),*)),* $(,)?) => {
        $(fn $name(self, $(_: $t),*) -> Result<Self::Ok, NotStruct> {
            Err(NotStruct)
        })*
    };
}

impl ser::Serializer for Keys {
    type Ok = Option<Vec<String>>;
    type Error = NotStruct;
    type SerializeSeq = Impossible<Self::Ok, NotStruct>;
    type SerializeTuple = Impossible<Self::Ok, NotStruct>;
    type SerializeTupleStruct = Impossible<Self::Ok, NotStruct>;
    type SerializeTupleVariant = Impossible<Self::Ok, NotStruct>;
    type SerializeMap = Impossible<Self::Ok, NotStruct>;
    type SerializeStruct = Fields;
    type SerializeStructVariant = Impossible<Self::Ok, NotStruct>;

    not_struct!(
        serialize_bool(bool),
        serialize_i8(i8),
        serialize_i16(i16),
        serialize_i32(i32),
        serialize_i64(i64),
        serialize_u8(u8),
        serialize_u16(u16),
        serialize_u32(u32),
        serialize_u64(u64),
        serialize_f32(f32),
        serialize_f64(f64),
        serialize_char(char),
        serialize_str(&str),
        serialize_bytes(&[u8]),
        serialize_none(),
        serialize_unit(),
        serialize_unit_struct(&'static str),
        serialize_unit_variant(&'static str, u32, &'static str),
    );

    fn serialize_some<T: ?Sized + Serialize>(self, _: &T) -> Result<Self::Ok, NotStruct> {
        Err(NotStruct)
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<Self::Ok, NotStruct> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<Self::Ok, NotStruct> {
        Err(NotStruct)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, NotStruct> {
        Err(NotStruct)
    }
    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, NotStruct> {
        Err(NotStruct)
    }
    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, NotStruct> {
        Err(NotStruct)
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, NotStruct> {
        Err(NotStruct)
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, NotStruct> {
        Err(NotStruct)
    }
    fn serialize_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStruct, NotStruct> {
        Ok(Fields(Vec::new()))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, NotStruct> {
        Err(NotStruct)
    }
}
