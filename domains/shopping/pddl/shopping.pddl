; domains/shopping/shopping.ixt in PDDL 2.1 (durative actions) with PDDL 2.2's timed initial literals, for
; running other planners on the problems of `mavtempo bench suite --write DIR --pddl`. Times are seconds
; from 08:00 (the problems' start). A walk takes the longest the .ixt allows, 20 min (15 to 20); buying 5 min.
(define (domain shopping)
  (:requirements :typing :durative-actions :timed-initial-literals)
  (:types place item)
  (:predicates
    (agent-at ?p - place)                    ; AT, none while walking
    (connected ?from - place ?to - place)    ; static
    (sells ?p - place ?i - item)             ; static
    (have ?i - item)
    (before-deadline-have ?i - item)         ; deleted at the item's deadline
    (before-horizon))                        ; deleted at 20:00

  (:durative-action go
    :parameters (?from - place ?to - place)
    :duration (= ?duration 1200)
    :condition (and (at start (connected ?from ?to)) (at start (agent-at ?from)) (at end (before-horizon)))
    :effect (and (at start (not (agent-at ?from))) (at end (agent-at ?to))))

  (:durative-action buy
    :parameters (?i - item ?p - place)
    :duration (= ?duration 300)
    :condition (and (at start (agent-at ?p)) (over all (agent-at ?p)) (at start (sells ?p ?i))
                    (at end (before-deadline-have ?i)) (at end (before-horizon)))
    :effect (at end (have ?i))))
