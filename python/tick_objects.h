// What a Python controller's callbacks receive: `obs` and `cmd` in update(obs, cmd), `pose` in
// initial_pose(pose). Each is alive for its call only; used after the call returned it raises
// ReferenceError instead of reaching into the run's buffers (which a kept object or array
// would otherwise read or write after the run moved on, or after it was freed).
//
// Arrays are NumPy copies, never views into the run: an Observation array is a read-only copy
// of the tick's values; a Command or StartPose array is a writable copy, made on first access
// and written back into the run when the call returns. A kept array thus stays valid, and a
// write to it after the call changes nothing.
#ifndef CLIMBSIM_PYTHON_TICK_OBJECTS_H_
#define CLIMBSIM_PYTHON_TICK_OBJECTS_H_

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <span>
#include <string>
#include <type_traits>

#include "sim/controller.h"

namespace climbsim::python {

namespace py = pybind11;

// Raises Python's ReferenceError for `what` (climbsim.Observation, ...) used after its call.
[[noreturn]] inline void Expired(const char* what) {
  const std::string message = std::string(what) +
                              " used after the controller call that received it returned: "
                              "keep the arrays you need (they are copies), not the object";
  PyErr_SetString(PyExc_ReferenceError, message.c_str());
  throw py::error_already_set();
}

// A new NumPy array holding a copy of n values (one allocation, one memcpy: this runs at
// every control tick).
template <class T>
py::array_t<T> NewCopy(const T* data, size_t n) {
  py::array_t<T> a(static_cast<py::ssize_t>(n));
  std::copy(data, data + n, a.mutable_data());
  return a;
}

// A read-only NumPy copy of a tick's values (a std::span or std::array).
template <class Values>
py::array ReadOnlyCopy(const Values& values) {
  using T = std::remove_cv_t<typename Values::value_type>;
  py::array_t<T> a = NewCopy<T>(values.data(), values.size());
  // What setflags(write=False) does, without a Python call.
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

// One writable array of a tick object: a NumPy copy of `target`, made on first access (the
// same array for every access until Flush), which Flush writes back into `target`.
template <class T>
class Slot {
 public:
  Slot(std::span<T> target, const char* name) : target_(target), name_(name) {}

  py::object Get() {
    if (!array_) array_ = NewCopy<T>(target_.data(), target_.size());
    return array_;
  }
  // Writes the array back (when it was made) and forgets it: the next Get copies afresh.
  void Flush() {
    if (!array_) return;
    // ensure() gives a C-ordered array of T whatever was done to the dtype or the strides.
    using Exact = py::array_t<T, py::array::c_style | py::array::forcecast>;
    auto a = py::isinstance<Exact>(array_) ? py::reinterpret_borrow<Exact>(array_)
                                           : Exact::ensure(array_);
    array_ = py::object();
    if (!a || static_cast<size_t>(a.size()) != target_.size()) {
      throw py::value_error(std::string(name_) + " must keep its " +
                            std::to_string(target_.size()) + " elements");
    }
    std::copy(a.data(), a.data() + a.size(), target_.begin());
  }
  void Drop() { array_ = py::object(); }

 private:
  std::span<T> target_;
  const char* name_;
  py::object array_;
};

// `obs` of update(obs, cmd).
class TickObservation {
 public:
  explicit TickObservation(const sim::Observation* obs) : obs_(obs) {}
  const sim::Observation& get() const {
    if (obs_ == nullptr) Expired("climbsim.Observation");
    return *obs_;
  }
  void Expire() { obs_ = nullptr; }

 private:
  const sim::Observation* obs_;
};

// `cmd` of update(obs, cmd).
class TickCommand {
 public:
  explicit TickCommand(sim::Command* cmd)
      : cmd_(cmd),
        target_(cmd->target_rad, "cmd.target_rad"),
        offset_(cmd->offset_rad, "cmd.offset_rad"),
        release_(cmd->release, "cmd.release"),
        kp_scale_(cmd->kp_scale, "cmd.kp_scale") {}
  py::object target() {
    Live();
    return target_.Get();
  }
  py::object offset() {
    Live();
    return offset_.Get();
  }
  py::object release() {
    Live();
    return release_.Get();
  }
  py::object kp_scale() {
    Live();
    return kp_scale_.Get();
  }
  // The command with the arrays written back: for a C++ controller's update called from
  // Python, whose writes the next array access then copies.
  sim::Command& Flushed() {
    Live();
    Flush();
    return *cmd_;
  }
  void Flush() {
    target_.Flush();
    offset_.Flush();
    release_.Flush();
    kp_scale_.Flush();
  }
  void Expire() {
    cmd_ = nullptr;
    target_.Drop();
    offset_.Drop();
    release_.Drop();
    kp_scale_.Drop();
  }

 private:
  void Live() const {
    if (cmd_ == nullptr) Expired("climbsim.Command");
  }
  sim::Command* cmd_;
  Slot<double> target_, offset_;
  Slot<uint8_t> release_;
  Slot<double> kp_scale_;
};

// `pose` of initial_pose(pose).
class TickPose {
 public:
  explicit TickPose(sim::StartPose* pose)
      : pose_(pose),
        joints_(pose->joint_angle_rad, "pose.joint_angle_rad"),
        base_(pose->base_pos_m, "pose.base_pos_m") {}
  py::object joints() {
    Live();
    return joints_.Get();
  }
  py::object base() {
    Live();
    return base_.Get();
  }
  sim::StartPose& Flushed() {
    Live();
    Flush();
    return *pose_;
  }
  void Flush() {
    joints_.Flush();
    base_.Flush();
  }
  void Expire() {
    pose_ = nullptr;
    joints_.Drop();
    base_.Drop();
  }

 private:
  void Live() const {
    if (pose_ == nullptr) Expired("climbsim.StartPose");
  }
  sim::StartPose* pose_;
  Slot<double> joints_, base_;
};

// A tick object handed to Python for one call, expired when the scope ends (the call
// returned or raised). Needs the GIL.
template <class T>
class TickScope {
 public:
  template <class P>
  explicit TickScope(P* p) : object_(py::cast(T(p))), tick_(object_.cast<T*>()) {}
  ~TickScope() { tick_->Expire(); }
  TickScope(const TickScope&) = delete;
  TickScope& operator=(const TickScope&) = delete;
  const py::object& object() const { return object_; }
  T& tick() { return *tick_; }

 private:
  py::object object_;
  T* tick_;
};

}  // namespace climbsim::python

#endif  // CLIMBSIM_PYTHON_TICK_OBJECTS_H_
