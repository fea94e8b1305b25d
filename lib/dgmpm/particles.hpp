#pragma once
// Material points as contiguous arrays (structure of arrays): one column per particle. The
// fields are listed once, in for_each_field; resizing, selection, the MPI records, checkpoints and
// seeding iterate over that list, so a new field is one member and one line there.

#include <Eigen/Core>
#include <vector>

namespace dgmpm {

// What the code that moves particles between arrays, ranks and files needs to know of a field.
struct FieldInfo {
  const char* name;
  bool stepped;   // changed by a step of fixed particles (ghosts take their owners' after each)
  bool optional;  // present only when asked for (Particles::tracks_reference)
};

// Per-field operations on the three kinds of column arrays a field may be: a fixed number of
// doubles per particle, one double, one int (held exactly in a double in MPI records).
namespace particle_field {
template <int R>
constexpr int width(const Eigen::Matrix<double, R, Eigen::Dynamic>&) {
  return R;
}
constexpr int width(const Eigen::VectorXd&) {
  return 1;
}
constexpr int width(const std::vector<int>&) {
  return 1;
}

// Resized to n columns; `keep`: the first columns kept (seeding appends bodies).
template <int R>
void resize(Eigen::Matrix<double, R, Eigen::Dynamic>& m, int n, bool keep) {
  keep ? m.conservativeResize(R, n) : m.resize(R, n);
}
inline void resize(Eigen::VectorXd& v, int n, bool keep) {
  keep ? v.conservativeResize(n) : v.resize(n);
}
inline void resize(std::vector<int>& v, int n, bool) {
  v.resize(static_cast<std::size_t>(n));
}

template <int R>
void copy(Eigen::Matrix<double, R, Eigen::Dynamic>& to, int i,
          const Eigen::Matrix<double, R, Eigen::Dynamic>& from, int j) {
  to.col(i) = from.col(j);
}
inline void copy(Eigen::VectorXd& to, int i, const Eigen::VectorXd& from, int j) {
  to[i] = from[j];
}
inline void copy(std::vector<int>& to, int i, const std::vector<int>& from, int j) {
  to[i] = from[j];
}

// Column i as width() doubles at out, and back.
template <int R>
void write(const Eigen::Matrix<double, R, Eigen::Dynamic>& m, int i, double* out) {
  for (int r = 0; r < R; ++r) out[r] = m(r, i);
}
inline void write(const Eigen::VectorXd& v, int i, double* out) {
  out[0] = v[i];
}
inline void write(const std::vector<int>& v, int i, double* out) {
  out[0] = v[i];
}
template <int R>
void read(Eigen::Matrix<double, R, Eigen::Dynamic>& m, int i, const double* in) {
  for (int r = 0; r < R; ++r) m(r, i) = in[r];
}
inline void read(Eigen::VectorXd& v, int i, const double* in) {
  v[i] = in[0];
}
inline void read(std::vector<int>& v, int i, const double* in) {
  v[i] = static_cast<int>(in[0]);
}
}  // namespace particle_field

// NInternal: the internal variables of the particles' physics (plastic strain, hardening...),
// none for elastic materials.
template <int Dim, int NComp, int NInternal = 0>
struct Particles {
  static constexpr int dim = Dim, n_comp = NComp, n_internal = NInternal;

  Eigen::Matrix<double, Dim, Eigen::Dynamic> position;
  Eigen::VectorXd mass;
  Eigen::VectorXd volume;
  Eigen::Matrix<double, NComp, Eigen::Dynamic> state;         // specific state q^s
  Eigen::Matrix<double, NInternal, Eigen::Dynamic> internal;  // the physics' internal variables
  std::vector<int> material;                                  // index into the scene's materials
  std::vector<int> id;                                        // creation order, for stable outputs
  Eigen::Matrix<double, Dim, Eigen::Dynamic> reference;       // initial position, when tracked
  bool tracks_reference = false;

  // Every field, in the order of checkpoints and MPI records: f(FieldInfo, array).
  template <class F>
  void for_each_field(F&& f) {
    fields(f, *this);
  }
  template <class F>
  void for_each_field(F&& f) const {
    fields(f, *this);
  }
  // The same fields of several particle sets side by side: f(FieldInfo, array of a, of b, ...).
  template <class F, class... Sets>
  static void for_each_field_of(F&& f, Sets&... sets) {
    fields(f, sets...);
  }

  int size() const { return static_cast<int>(mass.size()); }

  // Columns a field has for n particles: none for an optional field not tracked.
  int columns(const FieldInfo& info, int n) const {
    return info.optional && !tracks_reference ? 0 : n;
  }

  // n particles; `keep`: the first ones kept.
  void resize(int n, bool keep = false) {
    for_each_field([&](const FieldInfo& info, auto& field) {
      particle_field::resize(field, columns(info, n), keep);
    });
  }

  // The particles order[0], order[1], ... (any subset, in any order).
  Particles select(const std::vector<int>& order) const {
    Particles p;
    p.tracks_reference = tracks_reference;
    p.resize(static_cast<int>(order.size()));
    for_each_field_of(
        [&](const FieldInfo& info, auto& to, const auto& from) {
          if (p.columns(info, 1) == 0) return;
          for (int i = 0; i < p.size(); ++i) particle_field::copy(to, i, from, order[i]);
        },
        p, *this);
    return p;
  }

  // Doubles a record of one particle's fields takes (write_record), and the offset of its position.
  int record_width() const {
    int w = 0;
    for_each_field([&](const FieldInfo& info, const auto& field) {
      if (columns(info, 1)) w += particle_field::width(field);
    });
    return w;
  }
  static constexpr int record_position = 0;  // position is the first field

  // Particle i's fields appended to `out`, and read back from a record.
  void write_record(int i, std::vector<double>& out) const {
    for_each_field([&](const FieldInfo& info, const auto& field) {
      if (!columns(info, 1)) return;
      const std::size_t at = out.size();
      out.resize(at + static_cast<std::size_t>(particle_field::width(field)));
      particle_field::write(field, i, out.data() + at);
    });
  }
  void read_record(int i, const double* in) {
    for_each_field([&](const FieldInfo& info, auto& field) {
      if (!columns(info, 1)) return;
      particle_field::read(field, i, in);
      in += particle_field::width(field);
    });
  }

  // The fields a step of fixed particles changes (FieldInfo::stepped), stepped_width() doubles.
  int stepped_width() const {
    int w = 0;
    for_each_field([&](const FieldInfo& info, const auto& field) {
      if (info.stepped) w += particle_field::width(field);
    });
    return w;
  }
  void write_stepped(int i, double* out) const {
    for_each_field([&](const FieldInfo& info, const auto& field) {
      if (!info.stepped) return;
      particle_field::write(field, i, out);
      out += particle_field::width(field);
    });
  }
  void read_stepped(int i, const double* in) {
    for_each_field([&](const FieldInfo& info, auto& field) {
      if (!info.stepped) return;
      particle_field::read(field, i, in);
      in += particle_field::width(field);
    });
  }

 private:
  // The list of fields (position first: MPI records locate a particle by it).
  template <class F, class... Sets>
  static void fields(F& f, Sets&... s) {
    f(FieldInfo{"position", false, false}, s.position...);
    f(FieldInfo{"mass", false, false}, s.mass...);
    f(FieldInfo{"volume", false, false}, s.volume...);
    f(FieldInfo{"state", true, false}, s.state...);
    f(FieldInfo{"internal", true, false}, s.internal...);
    f(FieldInfo{"material", false, false}, s.material...);
    f(FieldInfo{"id", false, false}, s.id...);
    f(FieldInfo{"reference", false, true}, s.reference...);
  }
};

// The particle arrays of a physics (its state components and internal variables).
template <class Physics>
using ParticlesOf = Particles<Physics::dim, Physics::n_comp, Physics::n_internal>;

}  // namespace dgmpm
