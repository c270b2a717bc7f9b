#include "soltex/spec_proto/spec_from_proto.h"

#include <string>

#include "graph_proto.h"
#include "soltex/common/overloaded.h"
#include "soltex/common/spec_error.h"
#include "soltex/graph/compiled_graph.h"

namespace soltex {
namespace {

Axis axis_from(v1::Axis axis, const char* field) {
  switch (axis) {
    case v1::AXIS_X:
      return Axis::x;
    case v1::AXIS_Y:
      return Axis::y;
    case v1::AXIS_Z:
      return Axis::z;
    default:
      throw SpecError(field, std::to_string(axis), "must be AXIS_X, AXIS_Y or AXIS_Z");
  }
}

NoiseBasis basis_from(v1::NoiseBasis basis, const char* field) {
  switch (basis) {
    case v1::NOISE_BASIS_VALUE:
      return NoiseBasis::value;
    case v1::NOISE_BASIS_GRADIENT:
      return NoiseBasis::gradient;
    default:
      throw SpecError(field, std::to_string(basis),
                      "must be NOISE_BASIS_VALUE or NOISE_BASIS_GRADIENT");
  }
}

// Octave counts arrive unsigned; anything past the int range is reported as is.
int octave_from(uint32_t value, const char* field) {
  if (value > static_cast<uint32_t>(SpecLimits::kMaxOctave)) {
    throw SpecError(field, std::to_string(value),
                    "must be in [0, " + std::to_string(SpecLimits::kMaxOctave) + "]");
  }
  return static_cast<int>(value);
}

FractalParams fractal_from(const v1::Fractal& m, const std::string& prefix) {
  FractalParams f;
  if (m.has_scale()) f.scale = m.scale();
  if (m.has_octave_min())
    f.octave_min = octave_from(m.octave_min(), (prefix + ".octave_min").c_str());
  if (m.has_octave_max())
    f.octave_max = octave_from(m.octave_max(), (prefix + ".octave_max").c_str());
  f.basis = basis_from(m.basis(), (prefix + ".basis").c_str());
  f.signed_octaves = m.signed_octaves();
  return f;
}

v1::Fractal fractal_to(const FractalParams& f) {
  v1::Fractal m;
  m.set_scale(f.scale);
  m.set_octave_min(static_cast<uint32_t>(f.octave_min));
  m.set_octave_max(static_cast<uint32_t>(f.octave_max));
  m.set_basis(f.basis == NoiseBasis::value ? v1::NOISE_BASIS_VALUE : v1::NOISE_BASIS_GRADIENT);
  m.set_signed_octaves(f.signed_octaves);
  return m;
}

v1::Axis axis_to(Axis axis) {
  return static_cast<v1::Axis>(static_cast<int>(axis));
}

Pattern pattern_from(const v1::TextureSpec& m) {
  switch (m.pattern_case()) {
    case v1::TextureSpec::kStripes: {
      StripesParams p;
      const auto& s = m.stripes();
      if (s.has_width()) p.width = s.width();
      if (s.has_offset()) p.offset = s.offset();
      p.axis = axis_from(s.axis(), "stripes.axis");
      return p;
    }
    case v1::TextureSpec::kChecker: {
      CheckerParams p;
      const auto& c = m.checker();
      if (c.has_size()) p.size = {c.size().x(), c.size().y(), c.size().z()};
      if (c.has_offset()) p.offset = c.offset();
      p.three_d = c.three_d();
      return p;
    }
    case v1::TextureSpec::kColourCube: {
      ColourCubeParams p;
      if (m.colour_cube().has_period()) p.period = m.colour_cube().period();
      return p;
    }
    case v1::TextureSpec::kRings: {
      RingsParams p;
      const auto& r = m.rings();
      if (r.has_thickness()) p.thickness = r.thickness();
      if (r.has_base()) p.base = r.base();
      if (r.has_amplitude()) p.amplitude = r.amplitude();
      return p;
    }
    case v1::TextureSpec::kWood: {
      WoodParams p;
      const auto& w = m.wood();
      if (w.has_ring_spacing()) p.ring_spacing = w.ring_spacing();
      if (w.has_tilt_y()) p.tilt_y = w.tilt_y();
      if (w.has_tilt_z()) p.tilt_z = w.tilt_z();
      if (w.has_twist()) p.twist = w.twist();
      if (w.has_jitter()) p.jitter = w.jitter();
      if (w.has_jitter_scale()) p.jitter_scale = w.jitter_scale();
      if (w.has_grain_fraction()) p.grain_fraction = w.grain_fraction();
      return p;
    }
    case v1::TextureSpec::kNoise: {
      NoiseParams p;
      if (m.noise().has_scale()) p.scale = m.noise().scale();
      p.basis = basis_from(m.noise().basis(), "noise.basis");
      return p;
    }
    case v1::TextureSpec::kTurbulence:
      return TurbulenceParams{fractal_from(m.turbulence().fractal(), "turbulence.fractal")};
    case v1::TextureSpec::kMarble: {
      MarbleParams p;
      const auto& mm = m.marble();
      if (mm.has_frequency()) p.frequency = mm.frequency();
      if (mm.has_amplitude()) p.amplitude = mm.amplitude();
      switch (mm.ripple()) {
        case v1::RIPPLE_AXIS:
          p.ripple = Ripple::axis;
          break;
        case v1::RIPPLE_PRODUCT:
          p.ripple = Ripple::product;
          break;
        default:
          throw SpecError("marble.ripple", std::to_string(mm.ripple()),
                          "must be RIPPLE_AXIS or RIPPLE_PRODUCT");
      }
      p.axis = axis_from(mm.axis(), "marble.axis");
      p.turbulence = fractal_from(mm.turbulence(), "marble.turbulence");
      return p;
    }
    case v1::TextureSpec::kGraph:
      return {};  // from_proto() reads graphs
    case v1::TextureSpec::PATTERN_NOT_SET:
      break;
  }
  throw SpecError("pattern", "unset",
                  "exactly one of stripes, checker, colour_cube, rings, wood, noise, turbulence, "
                  "marble, graph must be set");
}

ScalarRange range_from(bool present, const v1::ScalarRange& r) {
  return present ? ScalarRange{r.low(), r.high()} : ScalarRange{};
}

}  // namespace

TextureSpec from_proto(const v1::TextureSpec& m) {
  TextureSpec spec;
  if (m.has_graph()) {
    spec.graph = graph::compile(graph_from_proto(m.graph()));
  } else {
    spec.pattern = pattern_from(m);
  }
  for (const auto& key : m.ramp().keys()) {
    spec.ramp.keys.push_back(
        {key.position(), {key.colour().r(), key.colour().g(), key.colour().b()}});
  }
  if (m.channels_size() > 0) {
    spec.channels = {false, false, false};
    for (int i = 0; i < m.channels_size(); ++i) {
      switch (m.channels(i)) {
        case v1::CHANNEL_COLOUR:
          spec.channels.colour = true;
          break;
        case v1::CHANNEL_OPACITY:
          spec.channels.opacity = true;
          break;
        case v1::CHANNEL_SPECULAR:
          spec.channels.specular = true;
          break;
        default:
          throw SpecError("channels[" + std::to_string(i) + "]", std::to_string(m.channels(i)),
                          "must be CHANNEL_COLOUR, CHANNEL_OPACITY or CHANNEL_SPECULAR");
      }
    }
  }
  spec.opacity = range_from(m.has_opacity(), m.opacity());
  spec.specular = range_from(m.has_specular(), m.specular());
  return validated(std::move(spec));
}

Volume from_proto(const v1::Volume& m) {
  Volume volume;
  volume.min = {m.min().x(), m.min().y(), m.min().z()};
  volume.max = {m.max().x(), m.max().y(), m.max().z()};
  if (m.finest_level_log2() > static_cast<uint32_t>(SpecLimits::kMaxFinestLevelLog2)) {
    throw SpecError("volume.finest_level_log2", std::to_string(m.finest_level_log2()),
                    "must be in [0, " + std::to_string(SpecLimits::kMaxFinestLevelLog2) + "]");
  }
  volume.finest_level_log2 = static_cast<int>(m.finest_level_log2());
  return validated(volume);
}

namespace {

void pattern_to(const Pattern& pattern, v1::TextureSpec& m) {
  std::visit(Overloaded{
                 [&](const StripesParams& p) {
                   auto* s = m.mutable_stripes();
                   s->set_width(p.width);
                   s->set_offset(p.offset);
                   s->set_axis(axis_to(p.axis));
                 },
                 [&](const CheckerParams& p) {
                   auto* c = m.mutable_checker();
                   c->mutable_size()->set_x(p.size.x);
                   c->mutable_size()->set_y(p.size.y);
                   c->mutable_size()->set_z(p.size.z);
                   c->set_offset(p.offset);
                   c->set_three_d(p.three_d);
                 },
                 [&](const ColourCubeParams& p) { m.mutable_colour_cube()->set_period(p.period); },
                 [&](const RingsParams& p) {
                   auto* r = m.mutable_rings();
                   r->set_thickness(p.thickness);
                   r->set_base(p.base);
                   r->set_amplitude(p.amplitude);
                 },
                 [&](const WoodParams& p) {
                   auto* w = m.mutable_wood();
                   w->set_ring_spacing(p.ring_spacing);
                   w->set_tilt_y(p.tilt_y);
                   w->set_tilt_z(p.tilt_z);
                   w->set_twist(p.twist);
                   w->set_jitter(p.jitter);
                   w->set_jitter_scale(p.jitter_scale);
                   w->set_grain_fraction(p.grain_fraction);
                 },
                 [&](const NoiseParams& p) {
                   m.mutable_noise()->set_scale(p.scale);
                   m.mutable_noise()->set_basis(p.basis == NoiseBasis::value
                                                    ? v1::NOISE_BASIS_VALUE
                                                    : v1::NOISE_BASIS_GRADIENT);
                 },
                 [&](const TurbulenceParams& p) {
                   *m.mutable_turbulence()->mutable_fractal() = fractal_to(p.fractal);
                 },
                 [&](const MarbleParams& p) {
                   auto* mm = m.mutable_marble();
                   mm->set_frequency(p.frequency);
                   mm->set_amplitude(p.amplitude);
                   mm->set_ripple(p.ripple == Ripple::axis ? v1::RIPPLE_AXIS : v1::RIPPLE_PRODUCT);
                   mm->set_axis(axis_to(p.axis));
                   *mm->mutable_turbulence() = fractal_to(p.turbulence);
                 },
             },
             pattern);
}

void ramp_and_channels_to(const TextureSpec& spec, v1::TextureSpec& m) {
  for (const RampKey& key : spec.ramp.keys) {
    auto* k = m.mutable_ramp()->add_keys();
    k->set_position(key.position);
    k->mutable_colour()->set_r(key.colour.r);
    k->mutable_colour()->set_g(key.colour.g);
    k->mutable_colour()->set_b(key.colour.b);
  }
  if (spec.channels.colour) m.add_channels(v1::CHANNEL_COLOUR);
  if (spec.channels.opacity) m.add_channels(v1::CHANNEL_OPACITY);
  if (spec.channels.specular) m.add_channels(v1::CHANNEL_SPECULAR);
  m.mutable_opacity()->set_low(spec.opacity.low);
  m.mutable_opacity()->set_high(spec.opacity.high);
  m.mutable_specular()->set_low(spec.specular.low);
  m.mutable_specular()->set_high(spec.specular.high);
}

}  // namespace

v1::TextureSpec to_proto(const TextureSpec& spec) {
  v1::TextureSpec m;
  if (spec.graph) {
    *m.mutable_graph() = graph_to_proto(graph::source_of(*spec.graph));
  } else {
    pattern_to(spec.pattern, m);
  }
  ramp_and_channels_to(spec, m);
  return m;
}

v1::Volume to_proto(const Volume& volume) {
  v1::Volume m;
  m.mutable_min()->set_x(volume.min.x);
  m.mutable_min()->set_y(volume.min.y);
  m.mutable_min()->set_z(volume.min.z);
  m.mutable_max()->set_x(volume.max.x);
  m.mutable_max()->set_y(volume.max.y);
  m.mutable_max()->set_z(volume.max.z);
  m.set_finest_level_log2(static_cast<uint32_t>(volume.finest_level_log2));
  return m;
}

}  // namespace soltex
