# The offline pipeline over every recorded session under a folder, for experiments:
#   make -f scripts/pipeline.mk SESSIONS=path/to/sessions OUT=out/pipeline -j4
# Per session NAME (a folder with session.json): OUT/NAME/views/view_NNN.ply (crop-cloud), model.ply and
# merge_report.json (merge-views), frame.json (estimate-frame), tooltip.json (find-tooltip), where the
# session has a ground_truth.json (simulated) evaluation.json (evaluate), model.png (the model with its
# frame and tooltip) and sheet.png (the session's views) (render), and report.html, all on one page
# (report); each step's stderr in OUT/NAME/logs/STEP.log.
#
# A failed session does not stop the others: every session is taken as far as it goes, then
# OUT/summary.csv (every session: done, with its figures, or failed, with the step and its error) is
# written and the table printed, and make fails (exit 2) when a session did. The same command again
# redoes only what failed or changed. `make -f scripts/pipeline.mk OUT/NAME/report.html` makes one
# session's outputs, as any make target, and stops at its first error.
SESSIONS ?= sessions
OUT ?= out/pipeline
BIN ?= build/bin
CONFIG ?=
config := $(if $(CONFIG),-c $(CONFIG))
self := $(lastword $(MAKEFILE_LIST))
scripts := $(dir $(self))
step = $(scripts)run-step.sh $(OUT)/$*/logs/$(1).log

names := $(notdir $(patsubst %/session.json,%,$(wildcard $(SESSIONS)/*/session.json)))
targets := $(foreach n,$(names),$(OUT)/$(n)/report.html)
# -n: the sessions' commands are shown, and no summary is written.
dry_run = $(findstring n,$(firstword -$(MAKEFLAGS)))

.PHONY: all sessions
# The sessions in a make of their own with -k, so that one failed session leaves the others to finish and
# the summary still runs; jobs (-j) are shared with it.
all:
	+@$(MAKE) -f $(self) -k --no-print-directory sessions; made=$$?; \
	  $(if $(dry_run),exit $$made,python3 $(scripts)session_summary.py $(SESSIONS) $(OUT) && [ $$made -eq 0 ])

sessions: $(targets)

.DELETE_ON_ERROR:
.SECONDEXPANSION:
# Every step's output is a result users look at, not an intermediate to delete.
.SECONDARY:

# Each step first removes what it makes: a step that fails leaves no output from an earlier run, which
# would be taken for its result (make deletes only a target the failed step changed). crop-cloud's views
# appear whole or not at all.
$(OUT)/%/views/.done: $(SESSIONS)/%/session.json
	rm -rf $(OUT)/$*/views $(OUT)/$*/views.tmp
	$(call step,crop_cloud) $(BIN)/crop-cloud -q $(config) $(SESSIONS)/$* --all -o $(OUT)/$*/views.tmp
	touch $(OUT)/$*/views.tmp/.done && mv $(OUT)/$*/views.tmp $(OUT)/$*/views

$(OUT)/%/model.ply: $(OUT)/%/views/.done
	rm -f $@ $(OUT)/$*/merge_report.json
	$(call step,merge_views) $(BIN)/merge-views -q $(config) $(OUT)/$*/views/view_*.ply -o $@ \
	  --report $(OUT)/$*/merge_report.json

$(OUT)/%/frame.json: $(OUT)/%/model.ply
	rm -f $@
	$(call step,estimate_frame) $(BIN)/estimate-frame -q $(config) $< -o $@

$(OUT)/%/tooltip.json: $(OUT)/%/model.ply $(OUT)/%/frame.json
	rm -f $@
	$(call step,find_tooltip) $(BIN)/find-tooltip -q $(config) $< --frame $(OUT)/$*/frame.json -o $@

$(OUT)/%/evaluation.json: $(OUT)/%/frame.json $(OUT)/%/tooltip.json $(SESSIONS)/%/ground_truth.json
	rm -f $@
	$(call step,evaluate) $(BIN)/evaluate -q --truth $(SESSIONS)/$*/ground_truth.json \
	  --frame $(OUT)/$*/frame.json --tooltip $(OUT)/$*/tooltip.json -o $@

$(OUT)/%/model.png: $(OUT)/%/model.ply $(OUT)/%/frame.json $(OUT)/%/tooltip.json
	rm -f $@
	$(call step,render_model) $(BIN)/render -q $(config) $< --frame $(OUT)/$*/frame.json \
	  --tooltip $(OUT)/$*/tooltip.json -o $@

$(OUT)/%/sheet.png: $(SESSIONS)/%/session.json
	rm -f $@
	$(call step,render_sheet) $(BIN)/render -q $(config) --session $(SESSIONS)/$* -o $@

# The report includes the evaluation when the session has a ground truth (a simulated one).
$(OUT)/%/report.html: $(OUT)/%/model.png $(OUT)/%/sheet.png \
                      $$(if $$(wildcard $(SESSIONS)/$$*/ground_truth.json),$(OUT)/$$*/evaluation.json)
	rm -f $@
	$(call step,report) $(BIN)/report -q $(OUT)/$* -o $@
