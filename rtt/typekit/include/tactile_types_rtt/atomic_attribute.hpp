// Read-only RTT attributes over std::atomic: a component's counters and
// statuses, written by its activity and read by other threads (the deployer's
// scripts, a reporter, a test's main thread).
//
// RTT's addAttribute(name, T&) binds a plain reference (ReferenceDataSource):
// a read from another thread while the hook writes is a data race by the C++
// memory model (docs/design.md, "Atomic attributes"), harmless as it may be for
// an aligned int on x86. Here the value lives in a std::atomic<T> that the
// hook stores to, and the attribute is an RTT Alias on a DataSource that loads
// it: the scripts and OCL's reporter read `Comp.frames` as before. Stores release and
// loads acquire: a reader that sees a value also sees what the writer did
// before it (e.g. a run's status string written before `finished`); on x86
// both are plain moves. Real-time: store() and load() are lock-free for the types used
// here (static_assert), no allocation after addAtomicAttribute().
#pragma once

#include <atomic>
#include <map>
#include <string>

#include <rtt/Attribute.hpp>
#include <rtt/ConfigurationInterface.hpp>
#include <rtt/internal/DataSource.hpp>

namespace tactile {

template <class T>
class AtomicDataSource : public RTT::internal::AssignableDataSource<T> {
  static_assert(std::atomic<T>::is_always_lock_free, "an attribute read from another thread must be lock-free");
  static_assert(sizeof(std::atomic<T>) == sizeof(T), "set() addresses the atomic's value");
  using Base = RTT::internal::AssignableDataSource<T>;

 public:
  explicit AtomicDataSource(std::atomic<T>& a) : a_(a) {}
  typename Base::result_t get() const override { return a_.load(std::memory_order_acquire); }
  typename Base::result_t value() const override { return get(); }
  /// A reference to a copy made in the calling thread (each thread its own),
  /// taken anew on every call.
  typename Base::const_reference_t rvalue() const override {
    thread_local T copy{};
    copy = get();
    return copy;
  }
  void set(typename Base::param_t t) override { a_.store(t, std::memory_order_release); }
  /// In-place writes (RTT's by-reference path; nothing here uses it): the
  /// atomic's own value, not synchronised.
  typename Base::reference_t set() override { return reinterpret_cast<T&>(a_); }
  AtomicDataSource<T>* clone() const override { return new AtomicDataSource<T>(a_); }
  AtomicDataSource<T>* copy(std::map<const RTT::base::DataSourceBase*, RTT::base::DataSourceBase*>&) const override {
    return const_cast<AtomicDataSource<T>*>(this);  // the same atomic: shared, as a reference is
  }

 private:
  std::atomic<T>& a_;
};

/// Adds `name`, over `a`, to the component's attributes. It is assignable as
/// RTT's reporting needs (OCL's reporter reports an attribute only through an
/// assignable data source); the component owns the value: scripts read it.
template <class T>
bool addAtomicAttribute(RTT::ConfigurationInterface& iface, const std::string& name, std::atomic<T>& a) {
  RTT::Alias alias(name, new AtomicDataSource<T>(a));
  return iface.addAttribute(alias);
}

/// The hooks' writes to the component's record (release: see above).
template <class T>
inline void record(std::atomic<T>& a, T v) {
  a.store(v, std::memory_order_release);
}
/// One more of a count.
template <class T>
inline void bump(std::atomic<T>& a) {
  a.fetch_add(1, std::memory_order_acq_rel);
}

/// The current value of an attribute of `iface` (a plain one or an atomic
/// alias), or `fallback` when there is none of that name and type.
template <class T>
T readAttribute(const RTT::ConfigurationInterface& iface, const std::string& name, T fallback = T{}) {
  RTT::base::AttributeBase* a = iface.getAttribute(name);
  if (!a) return fallback;
  RTT::base::DataSourceBase::shared_ptr base = a->getDataSource();
  RTT::internal::DataSource<T>* ds = RTT::internal::DataSource<T>::narrow(base.get());
  return ds ? ds->get() : fallback;
}

}  // namespace tactile
