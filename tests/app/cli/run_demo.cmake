# Runs `depthtouch demo` (a small clip of the built-in head scene, played with the simulated hand on
# the headless display) and checks its summary and files. Inputs: DEPTHTOUCH (executable), OUT (folder).

# fail(MESSAGE): keeps this run's output, force log and stats in OUT-failed-<time> (the next run
# writes over OUT; a failure seen once under load must be readable afterwards), then fails with
# MESSAGE.
function(fail msg)
    string(TIMESTAMP stamp "%Y%m%d-%H%M%S")
    set(kept ${OUT}-failed-${stamp})
    file(MAKE_DIRECTORY ${kept})
    file(WRITE ${kept}/summary.txt "${out}\n${err}\n${msg}\n")
    foreach(f force-log.csv stats.json)
        if(EXISTS ${OUT}/${f})
            file(COPY ${OUT}/${f} DESTINATION ${kept})
        endif()
    endforeach()
    message(FATAL_ERROR "${msg} (run kept in ${kept})")
endfunction()

# match_line(REGEX WHAT VAR...): fails the test with "no WHAT line" unless the demo's output matches
# REGEX; else sets each VAR, in order, to the next group of the match.
function(match_line regex what)
    if(NOT out MATCHES "${regex}")
        fail("no ${what} line")
    endif()
    set(group 1)
    foreach(var IN LISTS ARGN)
        set(${var} "${CMAKE_MATCH_${group}}" PARENT_SCOPE)
        math(EXPR group "${group} + 1")
    endforeach()
endfunction()

file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${DEPTHTOUCH} demo --duration 3 --size 160x120 --frames 20 --out ${OUT}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 240)
message("${out}")
if(NOT rc EQUAL 0)
    fail("depthtouch demo exited with ${rc}: ${err}")
endif()
# The main job's report is its own lines and the play's summary: the log's timestamped lines
# ("[12.345678] INFO  Backend: ...") only with DT_LOG, as for play.
if(NOT DEFINED ENV{DT_LOG} AND "${out}${err}" MATCHES "\\[[0-9]+\\.[0-9]+\\] +(INFO|WARN|DEBUG)")
    fail("the log's timestamped lines in the demo's report: ${CMAKE_MATCH_0}")
endif()
match_line("haptic updates +([0-9]+) \\(([0-9]+) in contact\\), [0-9]+ overruns, ([0-9]+) safety releases \\(([0-9]+) by the watchdog\\)"
    "haptic summary" updates contacts releases watchdog)
# The stroking hand must touch the face.
if(contacts LESS 100)
    fail("expected the hand in contact, got ${contacts} of ${updates} updates in contact")
endif()
match_line("frames +([0-9]+) received, ([0-9]+) presented, ([0-9]+) dropped" "frames summary"
    received presented dropped)
# The clip's material track: the head's skin and the curtain's cloth are felt with different
# stiffness (the material's scale of --stiffness 800 N/m; skin 0.56..1.5, cloth 0.66).
# A curtain the finger never pressed is said so ("curtain not touched"), never "nan N/m".
match_line("stiffness felt +head ([0-9]+) N/m, curtain ([0-9]+ N/m|not touched)" "stiffness felt" headK curtainK)
string(REGEX REPLACE " N/m$" "" curtainK "${curtainK}")
if(headK LESS 250 OR headK GREATER 1500 OR headK EQUAL 800)
    fail("stiffness felt on the head ${headK} N/m: not the skin's material")
endif()
# The curtain is touched briefly, near the head's silhouette. On a loaded machine a wake-up of the
# haptic thread over 6 ms late (or more than 5 deadlines missed) trips the task's watchdog, which
# zeroes the force and ramps it back in over 0.25 s: those updates read 0..500 N/m, and one run in
# ten read 51-282 N/m when they were most of the curtain's contact. The force log's gain column marks
# the ramp and the demo leaves those updates out, so the cloth's own 0.66 x 800 = 528 N/m is read.
# Under load the frames come late too and the HIP can pass the head's edge while the finger holds its
# proxy on the head's side, millimetres above the curtain, pushing at the bounded push's rate (one CI
# run read 133 N/m from 7 such updates): the demo counts only updates whose proxy rests on the surface.
if(NOT curtainK STREQUAL "not touched" AND (curtainK LESS 480 OR curtainK GREATER 580))
    fail("stiffness felt on the curtain ${curtainK} N/m: not the cloth's 525 N/m")
endif()
foreach(f force-log.csv stats.json force-psd.csv head-160x120-20-materials-sound.mkv snapshots/frame-000000.png)
    if(NOT EXISTS ${OUT}/${f})
        fail("missing ${OUT}/${f}")
    endif()
endforeach()
file(STRINGS ${OUT}/force-log.csv header LIMIT_COUNT 1)
if(NOT header STREQUAL "t,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released,play_t,gain")
    fail("force log header is '${header}'")
endif()
file(READ ${OUT}/stats.json stats)
# Every depth frame of the clip came with its material frame.
string(JSON materialFrames GET "${stats}" material_frames)
string(JSON materialMissing GET "${stats}" material_missing)
if(materialFrames LESS 20 OR NOT materialMissing EQUAL 0)
    fail("material track: ${materialFrames} frames decoded, ${materialMissing} missing")
endif()
string(JSON maxForce GET "${stats}" max_force_n)
string(JSON deviceMax GET "${stats}" device_max_force_n)
if(maxForce GREATER deviceMax)
    fail("force ${maxForce} N above the device maximum ${deviceMax} N")
endif()
# Seconds (a JSON number) to whole milliseconds, for CMake's integer arithmetic.
function(to_ms seconds var)
    if(NOT seconds MATCHES "^([0-9]+)(\\.([0-9]*))?")
        fail("not a number of seconds: ${seconds}")
    endif()
    string(SUBSTRING "${CMAKE_MATCH_3}000" 0 3 frac)
    math(EXPR ms "${CMAKE_MATCH_1} * 1000 + 1${frac} - 1000")
    set(${var} ${ms} PARENT_SCOPE)
endfunction()
# The run is in real time, so the counts are checked against the times the run measured, not
# against the 3 s asked for, and only where a count is impossible whatever the machine does (the
# exact accounting is checked on simulated time: HapticTaskTest.missedDeadlinesZeroTheForceAndItRampsBack
# counts every 1 ms period as an update or a missed deadline; the figures are printed here):
# - never more updates + missed periods than 1 ms periods of the haptic run, within 10 (the first
#   and the last wake-up); fewer is a loaded machine's lateness at the ends (13 short seen), not a
#   lost update;
# - the haptic loop ran at least the whole time the clip played, within 100 ms (it runs longer when
#   opening and stopping are slow: 126 ms on a loaded machine);
# - never more frames presented + dropped than frame periods (30 fps) of the playing time, within 3
#   (the first frame's preroll and the frames pending at the stop). Fewer is printed, not failed: a
#   starved machine leaves frames undecoded at the stop (the README's test command beside a busy
#   loop and a -Werror build: 56 presented + 2 dropped of 88 periods, 60 received, a 963 ms render
#   stall); that every due frame is presented or dropped, and dropped when it cannot catch up, is
#   checked exactly on simulated time (PlaybackSimTest.AStallDelaysFramesWithinTheMaxLatenessAndDropsThemBeyondIt,
#   PlaybackSimTest.FramesThatCannotCatchUpAreSkippedAfterThreeTimesTheMaxLateness).
string(JSON runS GET "${stats}" haptic_run_s)
string(JSON playingS GET "${stats}" playing_s)
string(JSON missed GET "${stats}" missed_periods)
string(JSON statsUpdates GET "${stats}" haptic_updates)
to_ms(${runS} runMs)
to_ms(${playingS} playingMs)
if(NOT statsUpdates EQUAL updates)
    fail("summary says ${updates} haptic updates, stats.json ${statsUpdates}")
endif()
# The summary's safety releases, the watchdog's among them said apart: stats.json's counts.
string(JSON statsReleases GET "${stats}" safety_releases)
string(JSON statsWatchdog GET "${stats}" watchdog_trips)
if(NOT statsReleases EQUAL releases OR NOT statsWatchdog EQUAL watchdog)
    fail("summary says ${releases} safety releases (${watchdog} by the watchdog), stats.json "
         "${statsReleases} (${statsWatchdog})")
endif()
math(EXPR periodGap "${updates} + ${missed} - ${runMs}")
message(STATUS "haptic run ${runMs} ms: ${updates} updates + ${missed} missed periods (gap ${periodGap}); playing ${playingMs} ms")
if(periodGap GREATER 10)
    fail("${updates} updates + ${missed} missed periods in ${runMs} ms of haptic run")
endif()
math(EXPR runGap "${runMs} - ${playingMs}")
if(runGap LESS -100)
    fail("haptic run ${runMs} ms, playing ${playingMs} ms")
endif()
math(EXPR frameGap "(${presented} + ${dropped}) * 1000 - ${playingMs} * 30")
message(STATUS "frames: ${presented} presented + ${dropped} dropped of ${received} received in ${playingMs} ms at 30 fps (gap ${frameGap} milliframes)")
if(frameGap GREATER 3000)
    fail("${presented} presented + ${dropped} dropped in ${playingMs} ms at 30 fps")
endif()
if(playingMs LESS 1000)
    fail("the clip played only ${playingMs} ms of the 3 s")
endif()
# The second run reuses the clip instead of rendering it again.
execute_process(COMMAND ${DEPTHTOUCH} demo --duration 1 --size 160x120 --frames 20 --out ${OUT}
    RESULT_VARIABLE rc2 OUTPUT_VARIABLE out2 ERROR_VARIABLE err2 TIMEOUT 120)
if(NOT rc2 EQUAL 0 OR out2 MATCHES "Rendering the built-in")
    fail("second demo run: exit ${rc2}, did it render again? ${out2} ${err2}")
endif()
