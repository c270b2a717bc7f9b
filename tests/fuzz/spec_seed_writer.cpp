// Writes serialized protocol messages into a directory, as the starting corpus of
// spec_parser_fuzz: a v1::TextureSpec per pattern (some with every field, some with only a
// few, as clients send them), ramps, channel lists and scalar ranges, and
// v1::RegisterTextureRequests over volumes of several shapes with every brick size and MIP mode.
//
//   spec_seed_writer <corpus-dir>
//
// It needs only the generated protobuf code, so it builds wherever the fuzz target does.

#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "seed_file.h"
#include "soltex/v1/brick_service.pb.h"
#include "soltex/v1/texture.pb.h"

namespace {

namespace v1 = soltex::v1;

struct NamedSpec {
  std::string name;
  v1::TextureSpec spec;
};

void set_vec3(v1::Vec3* v, double x, double y, double z) {
  v->set_x(x);
  v->set_y(y);
  v->set_z(z);
}

void add_ramp_key(v1::TextureSpec& spec, float position, float r, float g, float b) {
  v1::RampKey* key = spec.mutable_ramp()->add_keys();
  key->set_position(position);
  key->mutable_colour()->set_r(r);
  key->mutable_colour()->set_g(g);
  key->mutable_colour()->set_b(b);
}

void set_fractal(v1::Fractal* f, double scale, uint32_t octave_min, uint32_t octave_max,
                 v1::NoiseBasis basis, bool signed_octaves) {
  f->set_scale(scale);
  f->set_octave_min(octave_min);
  f->set_octave_max(octave_max);
  f->set_basis(basis);
  f->set_signed_octaves(signed_octaves);
}

std::vector<NamedSpec> seed_specs() {
  std::vector<NamedSpec> specs;
  const auto add = [&](std::string name, v1::TextureSpec spec) {
    specs.push_back({std::move(name), std::move(spec)});
  };
  {
    v1::TextureSpec s;
    s.mutable_stripes();  // every field at its default
    add("stripes-defaults", s);
    s.mutable_stripes()->set_width(0.25);
    s.mutable_stripes()->set_offset(0.5);
    s.mutable_stripes()->set_axis(v1::AXIS_Z);
    add_ramp_key(s, 0.0f, 1.0f, 0.85f, 0.1f);
    add_ramp_key(s, 1.0f, 0.8f, 0.1f, 0.05f);
    add("stripes-z-ramp", s);
  }
  {
    v1::TextureSpec s;
    set_vec3(s.mutable_checker()->mutable_size(), 0.4, 0.5, 0.6);
    s.mutable_checker()->set_offset(0.5);
    s.mutable_checker()->set_three_d(true);
    s.add_channels(v1::CHANNEL_COLOUR);
    s.add_channels(v1::CHANNEL_OPACITY);
    s.mutable_opacity()->set_low(0.2f);
    s.mutable_opacity()->set_high(0.9f);
    add("checker-3d-opacity", s);
  }
  {
    v1::TextureSpec s;
    s.mutable_colour_cube()->set_period(2.0);
    add("colour-cube", s);
  }
  {
    v1::TextureSpec s;
    s.mutable_rings()->set_thickness(0.1);
    s.mutable_rings()->set_base(0.2);
    s.mutable_rings()->set_amplitude(0.6);
    s.add_channels(v1::CHANNEL_SPECULAR);
    s.mutable_specular()->set_low(0.1f);
    s.mutable_specular()->set_high(0.7f);
    add("rings-specular", s);
  }
  {
    v1::TextureSpec s;
    v1::Wood* w = s.mutable_wood();
    w->set_ring_spacing(0.15);
    w->set_tilt_y(0.3);
    w->set_tilt_z(0.15);
    w->set_twist(0.5);
    w->set_jitter(0.6);
    w->set_jitter_scale(4.0);
    w->set_grain_fraction(0.2);
    add("wood-all-fields", s);
  }
  for (v1::NoiseBasis basis : {v1::NOISE_BASIS_VALUE, v1::NOISE_BASIS_GRADIENT}) {
    const std::string suffix = basis == v1::NOISE_BASIS_VALUE ? "value" : "gradient";
    v1::TextureSpec noise;
    noise.mutable_noise()->set_scale(8.0);
    noise.mutable_noise()->set_basis(basis);
    add("noise-" + suffix, noise);

    v1::TextureSpec turbulence;
    set_fractal(turbulence.mutable_turbulence()->mutable_fractal(), 4.0, 0, 5, basis,
                basis == v1::NOISE_BASIS_GRADIENT);
    add_ramp_key(turbulence, 0.0f, 0.05f, 0.05f, 0.2f);
    add_ramp_key(turbulence, 0.5f, 0.9f, 0.5f, 0.1f);
    add_ramp_key(turbulence, 1.0f, 1.0f, 1.0f, 0.8f);
    add("turbulence-" + suffix, turbulence);
  }
  {
    v1::TextureSpec s;
    v1::Marble* m = s.mutable_marble();
    m->set_frequency(1.5);
    m->set_amplitude(4.0);
    set_fractal(m->mutable_turbulence(), 2.0, 0, 6, v1::NOISE_BASIS_VALUE, false);
    add("marble-axis", s);
    m->set_ripple(v1::RIPPLE_PRODUCT);
    m->set_axis(v1::AXIS_Y);
    // The most octaves allowed, at the highest frequency the bounds admit.
    set_fractal(m->mutable_turbulence(), 10000.0, 8, 10, v1::NOISE_BASIS_GRADIENT, true);
    s.add_channels(v1::CHANNEL_COLOUR);
    s.add_channels(v1::CHANNEL_OPACITY);
    s.add_channels(v1::CHANNEL_SPECULAR);
    add("marble-product-all-channels", s);
  }
  {
    // A graph: position * 3 warped by a vector fractal, Worley cells mixed by a noise mask.
    v1::TextureSpec s;
    v1::Graph* g = s.mutable_graph();
    const auto node = [&](const char* name, const char* category, const char* type) {
      v1::GraphNode* n = g->add_nodes();
      n->set_name(name);
      n->set_category(category);
      n->set_type(type);
      return n;
    };
    const auto link = [](v1::GraphNode* n, const char* input, const char* from) {
      v1::GraphInput* in = n->add_inputs();
      in->set_name(input);
      in->set_node(from);
    };
    const auto number = [](v1::GraphNode* n, const char* input, double value) {
      v1::GraphInput* in = n->add_inputs();
      in->set_name(input);
      in->set_number(value);
    };
    node("p", "position", "");
    v1::GraphNode* scaled = node("p3", "multiply", "");
    link(scaled, "in1", "p");
    number(scaled, "in2", 3.0);
    v1::GraphNode* warp = node("warp", "fractal3d", "vector3");
    link(warp, "position", "p3");
    number(warp, "octaves", 4.0);
    v1::GraphNode* warped = node("q", "add", "");
    link(warped, "in1", "p3");
    link(warped, "in2", "warp");
    v1::GraphNode* cells = node("cells", "worleynoise3d", "");
    link(cells, "position", "q");
    v1::GraphInput* feature = cells->add_inputs();
    feature->set_name("feature");
    feature->set_choice("f2_minus_f1");
    v1::GraphNode* mask = node("mask", "noise3d", "");
    link(mask, "position", "p");
    v1::GraphNode* grey = node("grey", "convert", "color3");
    link(grey, "in", "cells");
    v1::GraphNode* colour = node("colour", "mix", "color3");
    v1::GraphInput* fg = colour->add_inputs();
    fg->set_name("fg");
    set_vec3(fg->mutable_vector(), 0.9, 0.8, 0.7);
    link(colour, "bg", "grey");
    link(colour, "mix", "mask");
    v1::GraphOutput* out = g->add_outputs();
    out->set_channel(v1::CHANNEL_COLOUR);
    out->set_node("colour");
    v1::GraphOutput* opacity = g->add_outputs();
    opacity->set_channel(v1::CHANNEL_OPACITY);
    opacity->set_node("cells");
    s.add_channels(v1::CHANNEL_COLOUR);
    s.add_channels(v1::CHANNEL_OPACITY);
    add("graph-warped-cells", s);
  }
  return specs;
}

struct NamedVolume {
  const char* name;
  double min[3];
  double max[3];
  uint32_t finest_level_log2;
};

// Unit cube, a far-away flat box, the largest coordinates allowed, a tiny box.
constexpr NamedVolume kVolumes[] = {
    {"unit", {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, 8},
    {"flat", {-4.5, -5.5, -4.5}, {4.5, -5.0, 4.5}, 9},
    {"huge", {-1e12, -1e12, -1e12}, {1e12, 1e12, 1e12}, 14},
    {"tiny", {1e5, 1e5, 1e5}, {1e5 + 1e-3, 1e5 + 1e-3, 1e5 + 1e-3}, 4},
};

}  // namespace

int main(int argc, char** argv) {
  return soltex::fuzz::seed_writer_main(argc, argv, {"corpus-dir"}, [](const auto& dirs) {
    const std::filesystem::path& dir = dirs[0];
    const std::vector<NamedSpec> specs = seed_specs();
    int written = 0;
    for (const NamedSpec& spec : specs) {
      soltex::fuzz::write_seed_file(dir / ("seed-spec-" + spec.name),
                                    spec.spec.SerializeAsString());
      ++written;
    }
    // Requests pair specs with volumes, brick sizes and MIP modes in rotation: every one of
    // each appears while the corpus stays small.
    const v1::MipMode modes[] = {v1::MIP_MODE_BAND_LIMITED, v1::MIP_MODE_POINT,
                                 v1::MIP_MODE_SUPERSAMPLED};
    const uint32_t brick_sizes[] = {0, 8, 16};
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const NamedVolume& volume = kVolumes[i % std::size(kVolumes)];
      v1::RegisterTextureRequest request;
      *request.mutable_spec() = specs[i].spec;
      set_vec3(request.mutable_volume()->mutable_min(), volume.min[0], volume.min[1],
               volume.min[2]);
      set_vec3(request.mutable_volume()->mutable_max(), volume.max[0], volume.max[1],
               volume.max[2]);
      request.mutable_volume()->set_finest_level_log2(volume.finest_level_log2);
      request.set_brick_size(brick_sizes[i % std::size(brick_sizes)]);
      request.set_mip_mode(modes[(i / 2) % std::size(modes)]);
      if (request.mip_mode() == v1::MIP_MODE_SUPERSAMPLED) {
        request.set_supersample(static_cast<uint32_t>(i % 3));  // 0 means 2
      }
      soltex::fuzz::write_seed_file(dir / ("seed-request-" + specs[i].name + "-" + volume.name),
                                    request.SerializeAsString());
      ++written;
    }
    std::printf("wrote %d seed messages to %s\n", written, dir.c_str());
  });
}
