// pybind11 casters for petsc4py.PETSc.Mat and petsc4py.PETSc.Vec arguments (Python -> C++ only).
//
// As DOLFINx's caster_petsc.h, the Python type is checked with petsc4py's C API
// (PyObject_TypeCheck against PyPetscMat_Type / PyPetscVec_Type) before the PETSc object is taken
// from it: integer handles and other objects with a `.handle` are refused. Differences: only Mat
// and Vec; a wrong type raises a TypeError naming the expected and the given type (not pybind11's
// generic "incompatible function arguments", so do not use these in overloaded functions); a
// petsc4py object without a PETSc object (not created, destroyed) raises ValueError. An optional
// argument is std::optional<Mat> (pybind11/stl.h maps None to std::nullopt); a plain Mat refuses
// None.
//
// petsc4py's C API lives in static variables of each translation unit and is imported on first
// use: include this header in one .cpp only (bindings.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include <petsc4py/petsc4py.h>

#include <string>

namespace rf::petsc4py_api {

inline void import_once() {
  if (PyPetscMat_Get != nullptr && PyPetscVec_Get != nullptr) return;
  if (import_petsc4py() != 0) throw pybind11::error_already_set();
}

template <class Handle>
struct Traits;

template <>
struct Traits<Mat> {
  static constexpr auto name = pybind11::detail::const_name("petsc4py.PETSc.Mat");
  static constexpr const char* text = "petsc4py.PETSc.Mat";
  static PyTypeObject* type() { return &PyPetscMat_Type; }
  static Mat get(PyObject* o) { return PyPetscMat_Get(o); }
};

template <>
struct Traits<Vec> {
  static constexpr auto name = pybind11::detail::const_name("petsc4py.PETSc.Vec");
  static constexpr const char* text = "petsc4py.PETSc.Vec";
  static PyTypeObject* type() { return &PyPetscVec_Type; }
  static Vec get(PyObject* o) { return PyPetscVec_Get(o); }
};

/// The PETSc handle held by `src`; throws TypeError / ValueError as described above.
template <class Handle>
Handle load(pybind11::handle src) {
  using T = Traits<Handle>;
  import_once();
  if (PyObject_TypeCheck(src.ptr(), T::type()) == 0) {
    std::string m = std::string("expected a ") + T::text + ", got " + Py_TYPE(src.ptr())->tp_name;
    if (PyLong_Check(src.ptr())) m += " (integer handles are not accepted: pass the petsc4py object)";
    throw pybind11::type_error(m);
  }
  const Handle h = T::get(src.ptr());
  if (PyErr_Occurred() != nullptr) throw pybind11::error_already_set();
  if (h == nullptr) throw pybind11::value_error(std::string("the ") + T::text + " holds no PETSc object (not created)");
  return h;
}

}  // namespace rf::petsc4py_api

namespace pybind11::detail {

/// Caster of a PETSc handle type (Mat = _p_Mat*): pybind11 looks it up under the pointee type.
template <class Handle>
class petsc4py_caster {
 public:
  static constexpr auto name = rf::petsc4py_api::Traits<Handle>::name;
  template <class>
  using cast_op_type = Handle;
  operator Handle() const { return value_; }

  bool load(handle src, bool /*convert*/) {
    if (!src) return false;
    value_ = rf::petsc4py_api::load<Handle>(src);
    return true;
  }

 private:
  Handle value_ = nullptr;
};

template <>
class type_caster<_p_Mat> : public petsc4py_caster<Mat> {};
template <>
class type_caster<_p_Vec> : public petsc4py_caster<Vec> {};

}  // namespace pybind11::detail
