#include "core/light_paths.h"

#include <deque>
#include <map>
#include <set>
#include <utility>

namespace penumbra {

namespace {

constexpr int kLetters = static_cast<int>(PathSet::kAlphabet.size());

int letterIndex(char c) {
    const size_t i = PathSet::kAlphabet.find(c);
    return i == std::string_view::npos ? -1 : static_cast<int>(i);
}

// Thompson's construction: a nondeterministic automaton with epsilon moves, built fragment by
// fragment while parsing (recursive descent, one function per precedence level).
class ThompsonParser {
  public:
    explicit ThompsonParser(std::string_view text) : text_(text) {}

    struct Fragment {
        int start, end;
    };
    struct State {
        std::vector<int> epsilon;
        int letter = -1, target = -1;
    };

    // The automaton of the whole expression; start state first, accepting state second.
    Fragment parseAll() {
        const Fragment f = alternation();
        skipSpaces();
        if (pos_ < text_.size())
            fail(text_[pos_] == ')' ? "')' without a matching '('" : "unexpected character");
        return f;
    }
    const std::vector<State>& states() const { return states_; }

  private:
    [[noreturn]] void fail(const std::string& what) const {
        throw PathExpressionError("light-path expression \"" + std::string(text_) +
                                  "\": at position " + std::to_string(pos_) + ": " + what +
                                  " (expected the letters L D S V E, | * + ? and parentheses)");
    }
    void skipSpaces() {
        while (pos_ < text_.size() && text_[pos_] == ' ')
            ++pos_;
    }
    int addState() {
        states_.emplace_back();
        return static_cast<int>(states_.size()) - 1;
    }
    Fragment epsilonFragment() {
        const int s = addState(), e = addState();
        states_[s].epsilon.push_back(e);
        return {s, e};
    }

    Fragment alternation() {
        Fragment f = concatenation();
        skipSpaces();
        while (pos_ < text_.size() && text_[pos_] == '|') {
            ++pos_;
            const Fragment g = concatenation();
            const int s = addState(), e = addState();
            states_[s].epsilon = {f.start, g.start};
            states_[f.end].epsilon.push_back(e);
            states_[g.end].epsilon.push_back(e);
            f = {s, e};
            skipSpaces();
        }
        return f;
    }

    Fragment concatenation() {
        std::optional<Fragment> f;
        while (true) {
            skipSpaces();
            if (pos_ >= text_.size() || text_[pos_] == '|' || text_[pos_] == ')')
                break;
            const Fragment g = postfix();
            if (f) {
                states_[f->end].epsilon.push_back(g.start);
                f->end = g.end;
            } else {
                f = g;
            }
        }
        return f ? *f : epsilonFragment();
    }

    Fragment postfix() {
        Fragment f = atom();
        while (true) {
            skipSpaces();
            if (pos_ >= text_.size())
                return f;
            const char op = text_[pos_];
            if (op != '*' && op != '+' && op != '?')
                return f;
            ++pos_;
            const int s = addState(), e = addState();
            states_[s].epsilon.push_back(f.start);
            states_[f.end].epsilon.push_back(e);
            if (op != '+')
                states_[s].epsilon.push_back(e);  // zero times
            if (op != '?')
                states_[f.end].epsilon.push_back(f.start);  // again
            f = {s, e};
        }
    }

    Fragment atom() {
        skipSpaces();
        if (pos_ >= text_.size())
            fail("expression ends where a letter or '(' was expected");
        const char c = text_[pos_];
        if (c == '(') {
            ++pos_;
            const Fragment f = alternation();
            skipSpaces();
            if (pos_ >= text_.size() || text_[pos_] != ')')
                fail("missing ')'");
            ++pos_;
            return f;
        }
        const int letter = letterIndex(c);
        if (letter < 0)
            fail(std::string("unexpected character '") + c + "'");
        ++pos_;
        const int s = addState(), e = addState();
        states_[s].letter = letter;
        states_[s].target = e;
        return {s, e};
    }

    std::string_view text_;
    size_t pos_ = 0;
    std::vector<State> states_;
};

using StateSet = std::set<int>;

void closeOverEpsilon(const std::vector<ThompsonParser::State>& states, StateSet& set) {
    std::vector<int> stack(set.begin(), set.end());
    while (!stack.empty()) {
        const int s = stack.back();
        stack.pop_back();
        for (const int t : states[s].epsilon) {
            if (set.insert(t).second)
                stack.push_back(t);
        }
    }
}

bool isSpace(char c) {
    return c == ' ';
}

}  // namespace

PathSet PathSet::parse(std::string_view expression) {
    PathSet result;
    result.expression_ = std::string(expression);
    bool blank = true;
    for (const char c : expression)
        blank = blank && isSpace(c);
    if (blank) {  // the empty set: one rejecting state that loops on every letter
        result.next_.push_back(Row{});
        result.accepting_.push_back(false);
        return result;
    }

    ThompsonParser parser(expression);
    const ThompsonParser::Fragment nfa = parser.parseAll();
    const auto& states = parser.states();

    // Subset construction; the empty subset becomes the dead state, so the automaton is complete.
    std::map<StateSet, int> index;
    std::vector<StateSet> subsets;
    StateSet start{nfa.start};
    closeOverEpsilon(states, start);
    index[start] = 0;
    subsets.push_back(start);
    for (size_t i = 0; i < subsets.size(); ++i) {
        Row row{};
        for (int letter = 0; letter < kLetters; ++letter) {
            StateSet moved;
            for (const int s : subsets[i]) {
                if (states[s].letter == letter)
                    moved.insert(states[s].target);
            }
            closeOverEpsilon(states, moved);
            const auto [it, inserted] = index.emplace(moved, static_cast<int>(subsets.size()));
            if (inserted)
                subsets.push_back(moved);
            row[letter] = it->second;
        }
        result.next_.push_back(row);
        result.accepting_.push_back(subsets[i].count(nfa.end) > 0);
    }
    return result;
}

PathSet PathSet::combine(const PathSet& other, Combine how, const std::string& expression) const {
    PathSet result;
    result.expression_ = expression;
    std::map<std::pair<int, int>, int> index;
    std::vector<std::pair<int, int>> pairs = {{0, 0}};
    index[{0, 0}] = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
        const auto [a, b] = pairs[i];
        Row row{};
        for (int letter = 0; letter < kLetters; ++letter) {
            const std::pair<int, int> next{next_[a][letter], other.next_[b][letter]};
            const auto [it, inserted] = index.emplace(next, static_cast<int>(pairs.size()));
            if (inserted)
                pairs.push_back(next);
            row[letter] = it->second;
        }
        const bool inA = accepting_[a], inB = other.accepting_[b];
        result.next_.push_back(row);
        result.accepting_.push_back(how == Combine::Intersection ? inA && inB
                                    : how == Combine::Union      ? inA || inB
                                                                 : inA && !inB);
    }
    return result;
}

PathSet PathSet::operator&(const PathSet& other) const {
    return combine(other, Combine::Intersection,
                   "(" + expression_ + ") & (" + other.expression_ + ")");
}

PathSet PathSet::operator|(const PathSet& other) const {
    return combine(other, Combine::Union, "(" + expression_ + ") | (" + other.expression_ + ")");
}

PathSet PathSet::operator-(const PathSet& other) const {
    return combine(other, Combine::Difference,
                   "(" + expression_ + ") - (" + other.expression_ + ")");
}

bool PathSet::contains(std::string_view path) const {
    int state = 0;
    for (const char c : path) {
        if (isSpace(c))
            continue;
        const int letter = letterIndex(c);
        if (letter < 0)
            return false;
        state = next_[state][letter];
    }
    return accepting_[state];
}

std::optional<std::string> PathSet::shortestPath() const {
    const std::vector<std::string> paths = shortestPaths(1);
    if (paths.empty())
        return std::nullopt;
    return paths.front();
}

std::vector<std::string> PathSet::shortestPaths(size_t count) const {
    // States from which an accepting state can be reached: only words through them can be
    // extended into paths of the set, so the search below never wanders into dead ends.
    const size_t n = next_.size();
    std::vector<bool> live = accepting_;
    for (bool changed = true; changed;) {
        changed = false;
        for (size_t s = 0; s < n; ++s) {
            for (int letter = 0; letter < kLetters && !live[s]; ++letter) {
                if (live[next_[s][letter]]) {
                    live[s] = true;
                    changed = true;
                }
            }
        }
    }

    // Breadth-first over words in shortlex order. The queue is bounded: the sets the planner
    // builds have short witnesses, and a caller asking for a few paths needs no more.
    constexpr size_t kMaxQueue = 1 << 16;
    std::vector<std::string> found;
    std::deque<std::pair<int, std::string>> queue;
    if (live[0])
        queue.emplace_back(0, "");
    while (!queue.empty() && found.size() < count) {
        auto [state, word] = std::move(queue.front());
        queue.pop_front();
        if (accepting_[state])
            found.push_back(word);
        for (int letter = 0; letter < kLetters && queue.size() < kMaxQueue; ++letter) {
            const int next = next_[state][letter];
            if (live[next])
                queue.emplace_back(next, word + (word.empty() ? "" : " ") + kAlphabet[letter]);
        }
    }
    return found;
}

}  // namespace penumbra
