// The enumerated settings of the VPP commands: each an enum class whose values are named in the
// code, with the words a config file spells them in. A value's number is what the checkpoints,
// summary.json "inputs" and a study's records store for the key (Setting::get), so the numbers
// never change; the words are the file's spelling, in the order of the numbers.
//   grains.radius_distribution  RadiusDistribution (scene/size_distribution.h)
//   grains.shape                GrainShape
//   foil.builder                FoilBuilder
//   process.pressure_model      PressureModel (vpp/membrane/gas.h)
//   process.waveform            Waveform
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

#include "scene/size_distribution.h"
#include "vpp/membrane/gas.h"

namespace vpp {

// Grain sizes: every grain grains.radius (the paper), uniform, lognormal, or a sieve curve.
using RadiusDistribution = scene::SizeDistribution::Kind;

// Grain shape: spheres (the paper), else rigid clumps (dem/clumps) with the volume of the sphere
// of the grain's radius: the built-in shapes (dem::builtin_clump_shapes(), in this order) or the
// members of grains.clump_template.
enum class GrainShape : int { Sphere = 0, Dimer = 1, Trimer = 2, Tetrahedron = 3, Pellet = 4, Template = 5 };

// The damper's foil: the paper's square grid (vpp/membrane/foil.h) or the membrane builder on the
// cylinder's lateral surface (vpp/membrane/membrane.h, membrane_tube_sites).
enum class FoilBuilder : int { Lattice = 0, Mesh = 1 };

// The stroke's shape: constant speed (the paper) or d = A (1 - cos 2 pi t / T) / 2.
enum class Waveform : int { Triangle = 0, Sine = 1 };

// The words of each enum, indexed by its values' numbers.
template <class E>
struct Words;
template <>
struct Words<RadiusDistribution> {
    static constexpr std::array<const char*, 4> words{"single", "uniform", "lognormal", "sieve"};
};
template <>
struct Words<GrainShape> {
    static constexpr std::array<const char*, 6> words{"sphere", "dimer", "trimer", "tetrahedron", "pellet", "template"};
};
template <>
struct Words<FoilBuilder> {
    static constexpr std::array<const char*, 2> words{"lattice", "mesh"};
};
template <>
struct Words<PressureModel> {
    static constexpr std::array<const char*, 2> words{"constant", "pump"};
};
template <>
struct Words<Waveform> {
    static constexpr std::array<const char*, 2> words{"triangle", "sine"};
};

// The file's word for a value.
template <class E>
constexpr const char* word_of(E v) {
    return Words<E>::words.at(std::size_t(v));
}

// The value a word stands for; nullopt for a word the setting does not have.
template <class E>
constexpr std::optional<E> from_word(std::string_view w) {
    for (std::size_t i = 0; i < Words<E>::words.size(); ++i)
        if (w == Words<E>::words[i]) return E(i);
    return std::nullopt;
}

// The value of a stored number (a checkpoint's, a record's); nullopt for a number no value has.
template <class E>
constexpr std::optional<E> from_number(double v) {
    if (!(v >= 0.0 && v < double(Words<E>::words.size()) && v == double(std::size_t(v)))) return std::nullopt;
    return E(std::size_t(v));
}

}  // namespace vpp
