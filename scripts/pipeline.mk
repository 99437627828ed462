# The offline pipeline over every recorded session under a folder, for experiments:
#   make -f scripts/pipeline.mk SESSIONS=path/to/sessions OUT=out/pipeline -j4
# Per session NAME (a folder with session.json): OUT/NAME/views/view_NNN.ply (crop-cloud), model.ply and
# merge_report.json (merge-views), frame.json (estimate-frame), tooltip.json (find-tooltip), where the
# session has a ground_truth.json (simulated) evaluation.json (evaluate), model.png (the model with its
# frame and tooltip) and sheet.png (the session's views) (render), and report.html, all on one page
# (report).
SESSIONS ?= sessions
OUT ?= out/pipeline
BIN ?= build/bin
CONFIG ?=
config := $(if $(CONFIG),-c $(CONFIG))

names := $(notdir $(patsubst %/session.json,%,$(wildcard $(SESSIONS)/*/session.json)))
targets := $(foreach n,$(names),$(OUT)/$(n)/report.html)

.PHONY: all
all: $(targets)

.DELETE_ON_ERROR:
.SECONDEXPANSION:
# Every step's output is a result users look at, not an intermediate to delete.
.SECONDARY:

$(OUT)/%/views/.done: $(SESSIONS)/%/session.json
	rm -rf $(OUT)/$*/views
	$(BIN)/crop-cloud -q $(config) $(SESSIONS)/$* --all -o $(OUT)/$*/views
	touch $@

$(OUT)/%/model.ply: $(OUT)/%/views/.done
	$(BIN)/merge-views -q $(config) $(OUT)/$*/views/view_*.ply -o $@ --report $(OUT)/$*/merge_report.json

$(OUT)/%/frame.json: $(OUT)/%/model.ply
	$(BIN)/estimate-frame -q $(config) $< -o $@

$(OUT)/%/tooltip.json: $(OUT)/%/model.ply $(OUT)/%/frame.json
	$(BIN)/find-tooltip -q $(config) $< --frame $(OUT)/$*/frame.json -o $@

$(OUT)/%/evaluation.json: $(OUT)/%/frame.json $(OUT)/%/tooltip.json $(SESSIONS)/%/ground_truth.json
	$(BIN)/evaluate -q --truth $(SESSIONS)/$*/ground_truth.json --frame $(OUT)/$*/frame.json \
	  --tooltip $(OUT)/$*/tooltip.json -o $@

$(OUT)/%/model.png: $(OUT)/%/model.ply $(OUT)/%/frame.json $(OUT)/%/tooltip.json
	$(BIN)/render -q $(config) $< --frame $(OUT)/$*/frame.json --tooltip $(OUT)/$*/tooltip.json -o $@

$(OUT)/%/sheet.png: $(SESSIONS)/%/session.json
	@mkdir -p $(@D)
	$(BIN)/render -q $(config) --session $(SESSIONS)/$* -o $@

# The report includes the evaluation when the session has a ground truth (a simulated one).
$(OUT)/%/report.html: $(OUT)/%/model.png $(OUT)/%/sheet.png \
                      $$(if $$(wildcard $(SESSIONS)/$$*/ground_truth.json),$(OUT)/$$*/evaluation.json)
	$(BIN)/report -q $(OUT)/$* -o $@
