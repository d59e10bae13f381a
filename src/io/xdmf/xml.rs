//! XML pieces of the XDMF writer: escaping and the `DataItem` forms (a whole HDF5 dataset, a
//! hyperslab of one, inline values).

use std::fmt::Display;

/// Number type and precision of an HDF5 dataset as XDMF names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Number {
    /// `f64`.
    Float8,
    /// `u32`.
    UInt4,
}

impl Number {
    fn xml_attrs(self) -> &'static str {
        match self {
            Number::Float8 => r#"NumberType="Float" Precision="8""#,
            Number::UInt4 => r#"NumberType="UInt" Precision="4""#,
        }
    }
}

/// Space-separated dimensions.
pub(super) fn dims(shape: &[usize]) -> String {
    join(shape)
}

fn join<T: Display>(values: &[T]) -> String {
    let mut s = String::new();
    for (i, v) in values.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        s.push_str(&v.to_string());
    }
    s
}

/// A `DataItem` reading the whole dataset `dataset` of the HDF5 file `h5` (already escaped).
pub(super) fn hdf_item(h5: &str, dataset: &str, shape: &[usize], number: Number) -> String {
    format!(
        "<DataItem Dimensions=\"{}\" {} Format=\"HDF\">{h5}:{}</DataItem>",
        dims(shape),
        number.xml_attrs(),
        escape(dataset)
    )
}

/// A `DataItem` reading the block of `count` values from `start` (unit stride) of the `f64`
/// dataset `dataset` of shape `shape`: XDMF 3's hyperslab form of an HDF5 reference,
/// `file:dataset|start:stride:count:shape` (each a space-separated list over the dimensions),
/// which ParaView's XDMF3 reader takes (its `ItemType="HyperSlab"` items come out empty).
pub(super) fn hyperslab_item(
    h5: &str,
    dataset: &str,
    shape: &[usize],
    start: &[usize],
    count: &[usize],
) -> String {
    let stride = vec![1; shape.len()];
    format!(
        "<DataItem Dimensions=\"{}\" {} Format=\"HDF\">{h5}:{}|{}:{}:{}:{}</DataItem>",
        dims(count),
        Number::Float8.xml_attrs(),
        escape(dataset),
        join(start),
        join(&stride),
        join(count),
        join(shape)
    )
}

/// A `DataItem` holding `values` inline (XML format).
pub(super) fn inline_item(values: &[u32], shape: &[usize]) -> String {
    format!(
        "<DataItem Dimensions=\"{}\" {} Format=\"XML\">{}</DataItem>",
        dims(shape),
        Number::UInt4.xml_attrs(),
        join(values)
    )
}

/// An `Attribute` element around `item`.
pub(super) fn attribute(name: &str, kind: &str, center: &str, item: &str) -> String {
    format!(
        "<Attribute Name=\"{}\" AttributeType=\"{kind}\" Center=\"{center}\">{item}</Attribute>\n",
        escape(name)
    )
}

/// Escapes the five XML special characters.
pub(super) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}
