#include "uascma/decision/random_mdp.h"

#include <algorithm>
#include <string>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/common/random.h"

namespace uascma::decision {
FiniteMdp MakeRandomMdp(int num_states, int num_actions, int successors, std::uint64_t seed) {
  if (num_states < 1 || num_actions < 1 || successors < 1 || successors > num_states) {
    throw InputError("random MDP", "size", "states >= 1, actions >= 1, 1 <= successors <= states");
  }
  std::vector<std::string> labels(static_cast<std::size_t>(num_states));
  for (int s = 0; s < num_states; ++s) labels[s] = std::to_string(s);
  std::vector<std::string> actions(static_cast<std::size_t>(num_actions));
  for (int a = 0; a < num_actions; ++a) actions[a] = "a" + std::to_string(a);
  FiniteMdpBuilder builder(std::move(labels), std::move(actions));
  RandomStream random(seed);
  std::vector<Transition> row(static_cast<std::size_t>(successors));
  for (StateIndex s = 0; s < num_states; ++s) {
    for (ActionIndex a = 0; a < num_actions; ++a) {
      double total = 0.0;
      for (int k = 0; k < successors; ++k) {
        StateIndex next;
        bool duplicate;
        do {  // distinct successors (rejection is cheap: successors << states in practice)
          next = static_cast<StateIndex>(random.UniformIndex(static_cast<std::uint64_t>(num_states)));
          duplicate =
              std::any_of(row.begin(), row.begin() + k, [next](const Transition& t) { return t.next_state == next; });
        } while (duplicate);
        row[k] = {next, 0.05 + random.Uniform()};
        total += row[k].probability;
      }
      std::sort(row.begin(), row.end(),
                [](const Transition& x, const Transition& y) { return x.next_state < y.next_state; });
      for (Transition& t : row) t.probability /= total;
      builder.AddRow(s, a, 2.0 * random.Uniform() - 1.0, row);
    }
  }
  return builder.Build();
}

}  // namespace uascma::decision
