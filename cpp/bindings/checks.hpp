#pragma once
// Argument checks shared by the bindings: inspect what Python passed before pybind11 converts it.
//
// pybind11's Eigen and float casters convert anything numpy can cast: complex arrays lose their
// imaginary part (with only a ComplexWarning), booleans become 0/1 and strings of digits become
// numbers. Bindings that users call directly take such arguments as py::object and convert them
// here, so a bad value is a TypeError / ValueError that names the argument and the rule, never a
// pybind11 signature dump or a silently truncated number.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

namespace satgnc::bindings::checks {

namespace py = pybind11;

/// "array of dtype complex128", "bool", "str": what the caller gave, for messages.
inline std::string describe(py::handle h) {
  if (py::isinstance<py::array>(h)) return "array of dtype " + std::string(py::str(h.attr("dtype")));
  return std::string(py::str(py::type::handle_of(h).attr("__name__")));
}

/// Name of a numpy dtype kind that is not a real number ("complex", "boolean", ...).
inline std::string kind_name(char kind) {
  switch (kind) {
    case 'c':
      return "complex";
    case 'b':
      return "boolean";
    case 'O':
      return "object";
    case 'U':
      return "string";
    case 'S':
      return "bytes";
    default:
      return std::string("'") + kind + "'-kind";
  }
}

/// Return h as a numpy array of a real dtype (float, signed or unsigned integer), or throw a
/// TypeError naming `name`. Complex, boolean, object, string input and ragged sequences are refused.
inline py::array real_array(py::handle h, const std::string& name) {
  if (h.is_none() || py::isinstance<py::str>(h) || py::isinstance<py::bytes>(h) ||
      py::isinstance<py::bool_>(h))
    throw py::type_error(name + ": must be a real numeric array, got " + describe(h));
  py::array a;
  if (py::isinstance<py::array>(h)) {
    a = py::reinterpret_borrow<py::array>(h);
  } else {
    try {
      a = py::module_::import("numpy").attr("asarray")(h);
    } catch (py::error_already_set& e) {
      throw py::type_error(name + ": must be a real numeric array (" + std::string(e.what()) + ")");
    }
  }
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(name + ": must be a real numeric array, got a " + kind_name(kind) + " array");
  return a;
}

/// "(3,)", "(2, 4)": numpy-style shape text.
inline std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// Convert h to the Eigen type T after the real-dtype check; a fixed size is checked with the
/// expected shape in the message. `finite` refuses NaN and Inf.
template <typename T>
T eigen_arg(py::handle h, const std::string& name, bool finite = true) {
  py::array a = real_array(h, name);
  constexpr int R = T::RowsAtCompileTime, C = T::ColsAtCompileTime;
  if constexpr (C == 1) {
    if (a.ndim() != 1 || (R != Eigen::Dynamic && a.shape(0) != R))
      throw py::value_error(name + ": must have shape (" + (R == Eigen::Dynamic ? "n" : std::to_string(R)) +
                            ",), got " + shape_text(a));
  } else {
    const bool ok =
        a.ndim() == 2 && (R == Eigen::Dynamic || a.shape(0) == R) && (C == Eigen::Dynamic || a.shape(1) == C);
    if (!ok)
      throw py::value_error(name + ": must have shape (" + (R == Eigen::Dynamic ? "n" : std::to_string(R)) +
                            ", " + (C == Eigen::Dynamic ? "m" : std::to_string(C)) + "), got " +
                            shape_text(a));
  }
  T out = a.cast<T>();
  if (finite && !out.allFinite()) throw py::value_error(name + ": must be finite (no NaN or Inf)");
  return out;
}

/// Convert h to a real 1-D list of numbers (times and the like).
inline std::vector<double> vector_arg(py::handle h, const std::string& name, bool finite = true) {
  py::array a = real_array(h, name);
  if (a.ndim() == 0) a = py::module_::import("numpy").attr("atleast_1d")(a);
  if (a.ndim() != 1) throw py::value_error(name + ": must be one-dimensional, got shape " + shape_text(a));
  std::vector<double> out = a.cast<std::vector<double>>();
  if (finite)
    for (double v : out)
      if (!std::isfinite(v)) throw py::value_error(name + ": must be finite (no NaN or Inf)");
  return out;
}

/// A real number: int or float (numpy scalars too), never bool, complex or str.
inline double real_arg(py::handle h, const std::string& name, bool finite = true) {
  const bool is_real_scalar =
      (py::isinstance<py::float_>(h) || py::isinstance<py::int_>(h)) && !py::isinstance<py::bool_>(h);
  bool ok = is_real_scalar;
  if (!ok && py::hasattr(h, "dtype") && py::hasattr(h, "ndim") && h.attr("ndim").cast<int>() == 0) {
    const char kind = py::array(h.attr("__array__")()).dtype().kind();
    ok = kind == 'f' || kind == 'i' || kind == 'u';
  }
  if (!ok) throw py::type_error(name + ": must be a real number, got " + describe(h));
  const double v = py::float_(py::reinterpret_borrow<py::object>(h)).cast<double>();
  if (std::isnan(v) || (finite && !std::isfinite(v)))
    throw py::value_error(name + ": must be finite, got " + std::string(py::str(py::float_(v))));
  return v;
}

/// A bool (Python or numpy), never an int or a string such as "false".
inline bool bool_arg(py::handle h, const std::string& name) {
  if (py::isinstance<py::bool_>(h)) return h.cast<bool>();
  if (py::hasattr(h, "dtype") && std::string(py::str(py::type::handle_of(h).attr("__name__"))) == "bool_")
    return py::bool_(py::reinterpret_borrow<py::object>(h)).cast<bool>();
  throw py::type_error(name + ": must be true or false (a bool), got " + describe(h));
}

/// An integer in [low, high], never a float (even 2.0) or a bool.
inline long long int_arg(py::handle h, const std::string& name, long long low, long long high) {
  const bool is_int =
      (py::isinstance<py::int_>(h) && !py::isinstance<py::bool_>(h)) ||
      (py::hasattr(h, "dtype") && py::hasattr(h, "__index__") && !py::isinstance<py::bool_>(h) &&
       std::string(py::str(py::type::handle_of(h).attr("__name__"))) != "bool_");
  if (!is_int) throw py::type_error(name + ": must be an integer, got " + describe(h));
  const py::int_ i(py::reinterpret_borrow<py::object>(h));
  // Compare as Python ints: a value beyond 64 bits must not wrap.
  if (i < py::int_(low) || i > py::int_(high))
    throw py::value_error(name + ": must be in [" + std::to_string(low) + ", " + std::to_string(high) +
                          "], got " + std::string(py::str(i)));
  return i.cast<long long>();
}

/// Names of the settable fields (properties with a setter) of the Python class `cls`, sorted.
inline std::vector<std::string> settable_fields(py::handle cls) {
  std::vector<std::string> out;
  const py::object property = py::module_::import("builtins").attr("property");
  for (py::handle name : py::list(py::module_::import("builtins").attr("dir")(cls))) {
    const std::string n = py::str(name);
    if (n.rfind("_", 0) == 0) continue;
    const py::object attr = py::getattr(cls, name, py::none());
    if (py::isinstance(attr, property) && !attr.attr("fset").is_none()) out.push_back(n);
  }
  return out;
}

/// Add a keyword constructor `Name(field=value, ...)` to the bound settings class `name` of `m`
/// (beside its `Name()`): each keyword is assigned through the class's Python property, so it gets
/// the same checks as `s.field = value` (types, NaN, the class's own validate() rule for that field,
/// enum names as strings). An unknown keyword is a TypeError naming it and the accepted fields.
template <typename T>
void settings_from_kwargs(py::module_& m, const char* name) {
  py::class_<T> cls(m.attr(name));
  const std::string cls_name = name;
  cls.def(py::init([cls_name](const py::kwargs& kwargs) {
            py::object obj = py::cast(T{});
            const py::handle type = py::type::handle_of(obj);
            const std::vector<std::string> fields = settable_fields(type);
            for (const auto& item : kwargs) {
              const std::string key = py::str(item.first);
              bool known = false;
              for (const std::string& f : fields) known = known || f == key;
              if (!known) {
                std::string list;
                for (const std::string& f : fields) list += (list.empty() ? "" : ", ") + f;
                throw py::type_error(key + ": unknown keyword of " + cls_name + " (accepted: " + list + ")");
              }
              py::setattr(obj, item.first, item.second);
            }
            return obj.cast<T>();
          }),
          "Keyword construction: every keyword is a field name (checked as an assignment would be).");
}

}  // namespace satgnc::bindings::checks
