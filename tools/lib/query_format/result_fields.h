// Internal: the fields of a result line (docs/query-format.md), in the order
// they are written, for the writer (query_file.cpp) and the reader
// (trace_records.cpp) alike. A new result field is added here (and, for a new
// kind of value, an overload in both visitors).
//
// A visitor is called as v(key, field) for each field, and v.material(key,
// index) for the material (written as its name; not read back).
#pragma once

namespace cmkit::detail {

/// fraction, endpos, endaxis: the fields of a trace before its contact.
template <typename Visitor, typename Trace>
void visitTraceFields(Visitor& v, Trace& t) {
  v("fraction", t.fraction);
  v("endpos", t.endPos);
  v("endaxis", t.endAxis);
}

/// The fields of a contact (after a trace's, or numbered in a contacts result).
template <typename Visitor, typename Contact>
void visitContactFields(Visitor& v, Contact& c) {
  v("type", c.type);
  v("point", c.point);
  v("normal", c.normal);
  v("dist", c.dist);
  v("contents", c.contents);
  v.material("material", c.material);
  v("modelfeature", c.modelFeature);
  v("trmfeature", c.trmFeature);
}

/// The field a contact of a contacts query along a rotation has after those
/// of visitContactFields: the degrees turned to it. Written for those
/// queries only, so that every other result line stays as the reference
/// files have it; read wherever present.
template <typename Visitor, typename Contact>
void visitRotationContactFields(Visitor& v, Contact& c) {
  v("angle", c.angle);
}

/// The field a world query's answer (cmkit query --world) adds after the
/// trace's, or after each contact's (numbered): the name of the entity hit
/// ("worldspawn" for the world model). Written only when an entity was hit;
/// read wherever present (v.entity(key, name)).
template <typename Visitor, typename Name>
void visitEntityField(Visitor& v, Name& name) {
  v.entity("entity", name);
}

}  // namespace cmkit::detail
