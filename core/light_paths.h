// Sets of light paths in Heckbert's notation (Heckbert 1990, "Adaptive Radiosity Textures for
// Bidirectional Ray Tracing"): a path is a word from the light to the eye over the vertex
// classes L (light), D (diffuse or rough glossy scattering), S (specular: mirror, smooth glass),
// V (a scattering event in a participating medium; no pass produces it yet) and E (the eye), and
// a set of paths is a regular expression over them, e.g. "L S+ D S* E" for caustics.
//
// Each pass declares the paths its image contribution holds; the pipeline planner intersects and
// unites the declarations to prove that no path is counted twice and to name the paths no pass
// counts. Regular languages are closed under both operations and their emptiness is decidable,
// so the check is exact: each set is held as a complete deterministic automaton (Thompson's
// construction, then the subset construction: Hopcroft, Motwani and Ullman, "Introduction to
// Automata Theory", sections 2.3 and 3.2), and set operations use the product automaton
// (ibid. 4.2.1).
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// A malformed path expression; what() names the position (0-based) and the problem.
class PathExpressionError : public std::invalid_argument {
  public:
    using std::invalid_argument::invalid_argument;
};

class PathSet {
  public:
    // The vertex classes, in the order of the automaton's alphabet.
    static constexpr std::string_view kAlphabet = "LDSVE";

    // Parses an expression: the letters of kAlphabet, concatenation, alternation `|`, the
    // postfix operators `*`, `+` and `?`, and parentheses; spaces are ignored. "" is the
    // empty set. Throws PathExpressionError.
    static PathSet parse(std::string_view expression);

    // The expression the set was parsed from, or built from with the operators below.
    const std::string& expression() const { return expression_; }

    PathSet operator&(const PathSet& other) const;  // intersection
    PathSet operator|(const PathSet& other) const;  // union
    PathSet operator-(const PathSet& other) const;  // difference

    bool empty() const { return !shortestPath().has_value(); }
    // Whether the path (a word over kAlphabet, spaces ignored) is in the set.
    bool contains(std::string_view path) const;
    // A shortest path in the set, letters separated by spaces ("L S D E"); the first in
    // alphabet order among those of that length. Nothing for the empty set.
    std::optional<std::string> shortestPath() const;
    // Up to `count` of the shortest paths in the set, shortest first, in alphabet order
    // within a length.
    std::vector<std::string> shortestPaths(size_t count) const;

  private:
    using Row = std::array<int, kAlphabet.size()>;
    enum class Combine { Intersection, Union, Difference };

    PathSet combine(const PathSet& other, Combine how, const std::string& expression) const;

    std::string expression_;
    // Complete deterministic automaton: state 0 is the start; next_[state][letter] is a state.
    std::vector<Row> next_;
    std::vector<bool> accepting_;
};

}  // namespace penumbra
