#include "line_scheduling/line_turns.h"

#include <algorithm>
#include <tuple>

namespace tiltgate {

namespace {

// Keeps in `best` the claim that `key` ranks first (the smallest key; none: `candidate`).
template <class Key>
void keep_first(std::optional<std::size_t>& best, std::size_t candidate,
                std::span<const TurnClaim> claims, Key key) {
  if (!best || key(claims[candidate]) < key(claims[*best])) best = candidate;
}

auto by_due(const TurnClaim& c) { return std::tuple(c.due, c.order); }
auto by_retry(const TurnClaim& c) { return std::tuple(c.retry, c.due, c.order); }
auto by_order(const TurnClaim& c) { return c.order; }

}  // namespace

std::optional<LineTurns::Other> LineTurns::other_of(const TurnClaim& claim) {
  if (claim.failing) return failing;
  switch (claim.kind) {
    case TurnKind::poll: return std::nullopt;  // a healthy poll: the rounds' own
    case TurnKind::write: return write;
    case TurnKind::forward:
    case TurnKind::command: return exchange;
  }
  return std::nullopt;
}

SteadyClock::time_point LineTurns::command_allowed_at(
    std::optional<SteadyClock::time_point> next_poll, SteadyClock::time_point now) const {
  // It fits before the polls (a line with none, or a first command, always).
  if (!next_poll || *next_poll >= now + command_held_) return now;
  const SteadyClock::duration wait =
      std::min<SteadyClock::duration>(command_held_ * kLineTimePerCommandTime, kCommandMaxWait);
  return std::max(now, command_ended_ + wait);
}

TurnChoice LineTurns::choose(std::span<const TurnClaim> claims, SteadyClock::time_point now) const {
  std::optional<std::size_t> owed, due_poll, first_write, first_failing, first_command,
      next_forward;
  std::optional<SteadyClock::time_point> next_poll;  // the earliest healthy poll, due or not
  TurnChoice choice;
  // Forwarded requests round robin: the clients after the last one served come first.
  const auto rotated = [this](const TurnClaim& c) {
    return std::tuple(c.client <= last_client_, c.client, c.order);
  };
  for (std::size_t i = 0; i < claims.size(); ++i) {
    const TurnClaim& claim = claims[i];
    if (claim.kind == TurnKind::poll && !claim.failing && (!next_poll || claim.due < *next_poll))
      next_poll = claim.due;
    if (claim.due > now) {
      if (!choice.next_due || claim.due < *choice.next_due) choice.next_due = claim.due;
      continue;
    }
    const std::optional<Other> other = other_of(claim);
    if (!other) {
      keep_first(claim.due <= round_until_ ? owed : due_poll, i, claims, by_due);
    } else if (*other == write) {
      keep_first(first_write, i, claims, by_order);
    } else if (*other == failing) {
      keep_first(first_failing, i, claims, by_retry);
    } else if (claim.kind == TurnKind::command) {
      keep_first(first_command, i, claims, by_order);
    } else {
      keep_first(next_forward, i, claims, rotated);
    }
  }
  if (owed) {
    choice.turn = owed;
    choice.owed = true;
    choice.held = first_failing;
    choice.next_due.reset();
    return choice;
  }
  // A command's transaction takes the line's spare time, or waits for its share.
  if (first_command) {
    const SteadyClock::time_point allowed = command_allowed_at(next_poll, now);
    if (allowed > now) {
      first_command.reset();
      if (!choice.next_due || allowed < *choice.next_due) choice.next_due = allowed;
    }
  }
  // Commands and forwarded requests take turns when both wait.
  std::optional<std::size_t> exchange_turn = first_command ? first_command : next_forward;
  if (first_command && next_forward && command_last_) exchange_turn = next_forward;
  const std::array<std::optional<std::size_t>, other_kinds> waiting{first_write, exchange_turn,
                                                                    first_failing};
  std::optional<std::size_t> least_recent;
  for (std::size_t kind = 0; kind < other_kinds; ++kind) {
    if (!waiting[kind]) continue;
    if (!least_recent || last_turn_[kind] < last_turn_[*least_recent]) least_recent = kind;
  }
  if (least_recent) {
    choice.turn = waiting[*least_recent];
  } else {
    choice.turn = due_poll;
  }
  if (choice.turn) choice.next_due.reset();
  return choice;
}

void LineTurns::ended(const TurnClaim& claim, SteadyClock::time_point end,
                      SteadyClock::duration held) {
  const std::optional<Other> other = other_of(claim);
  if (!other) return;
  round_until_ = end;
  last_turn_[*other] = ++turns_;
  if (claim.kind == TurnKind::command) {  // a retry's turn (failing) counts to its share too
    command_ended_ = end;
    command_held_ = held;
  }
  if (*other != exchange) return;
  command_last_ = claim.kind == TurnKind::command;
  if (claim.kind == TurnKind::forward) last_client_ = claim.client;
}

}  // namespace tiltgate
