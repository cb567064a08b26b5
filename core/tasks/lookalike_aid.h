#pragma once
// What an agent is told of a task's look-alikes under each aid (episode::LookalikeAid): the task
// text and the first hint that the scene-graph service, the audit page and the cost estimate
// give, and the label each look-alike's close-up carries (render/close_ups.h), so the three agree.

#include <map>
#include <string>
#include <vector>

#include "core/episode/rules.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

/// Each look-alike's close-up label: 1, 2, ... in the order `identify` first names the objects,
/// one per object (an object two parts of a Level 3 task name is one close-up).
std::map<std::string, int> close_up_labels(const std::vector<Identification>& identify);

/// "the cup in close-up 2": how the text names look-alike `id` under the aid kImage, `label` its
/// close-up's; the same words the audit asks with.
std::string close_up_words(const Identification& id, int label);

/// How a task names `id` under `aid`: its words (the phrase), or close_up_words under kImage.
std::string named_as(const Identification& id, const std::vector<Identification>& identify,
                     episode::LookalikeAid aid);

/// `text` (of task `task_id`) with each look-alike's words ("the second cup from the left") replaced by "the cup
/// in close-up k". An identification takes the occurrence of its phrase whose next platform name
/// is its own platform ("the leftmost book from shelf_1 and the leftmost book from shelf_3"),
/// else the first one after the previous identification's (texts name objects in `identify`
/// order); an object named twice ("put X where Y is, and Y where X is") is replaced both times.
/// @throws mtg::Error naming the task when a phrase is not in its text.
std::string text_with_close_ups(const std::string& task_id, const std::string& text,
                                const std::vector<Identification>& identify);

struct TaskWords {
  std::string text;  // the instruction as the agent reads it
  std::string hint;  // the first observation's hint ("" without look-alikes)
};

/// What the first observation says of a task (its id, text and look-alikes) under `aid`;
/// `with_images`: the observations carry images (the close-ups are sent).
/// @throws mtg::Error when `aid` is kImage without images: nothing would tell the look-alikes apart.
TaskWords task_words(const std::string& task_id, const std::string& text, const std::vector<Identification>& identify,
                     episode::LookalikeAid aid, bool with_images);

}  // namespace mtg::tasks
